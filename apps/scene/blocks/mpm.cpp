/// @file mpm.cpp
/// The `mpm` block: the MPM fluid + Belytschko-Tsay membrane examples of Lian, Liu & Zhang (2014),
/// section 7 (coupling/mpm/README.md). Every key defaults to the paper's value, so
/// `{"mpm": {"example": "gas_expansion"}}` plus `simulation.end_time` is a complete scene.
#include <fmt/format.h>

#include <cmath>

#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {
namespace {

Field contact() {
  return Field::object("contact", "Grid contact between particles and membrane (section 5).", {
      Field::enumeration("mode", {"slip", "stick"},
                         "`slip`: Coulomb sliding (eqs. 56-58); `stick`: no relative tangential motion "
                         "(eq. 55).").def("slip"),
      Field::number("friction", "", "Coulomb coefficient mu of eq. (58) (slip mode).").at_least(0).def(0.0),
      Field::number("distance_factor", "",
                    "A contact found in momentum form (eq. 52) is kept only if the membrane is within "
                    "this many cells of the particles (the membrane is stopped at most that far from the "
                    "particle surface).")
          .greater(0).at_most(1).def(0.25),
  });
}

/// particle_spacing = cell / n with n = 1, 2, 3 or 4: a whole number of particles per cell and
/// direction, so that the examples' lattices sit at the in-cell positions (i + 1/2) / n and never on
/// a node plane (where a particle's far corners get no mass; such a lattice blew up in contact,
/// coupling/mpm/README.md "Known limitations").
void spacing_fits_cell(const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
  if (!o.contains("cell") || !o.contains("particle_spacing")) return;
  const double h = o["cell"].get<double>(), s = o["particle_spacing"].get<double>();
  const double n = h / s;
  if (s > h || s < h / 4 || std::abs(n - std::round(n)) > 1e-9 * n)
    issues.push_back({pointer_append(ptr, "particle_spacing"),
                      fmt::format("expected cell / n for n = 1, 2, 3 or 4 (a whole number of particles per cell "
                                  "and direction: {}, {}, {} or {} [m] for cell = {}), got {}",
                                  h, h / 2, h / 3, h / 4, h, s)});
}

std::vector<Field> sphere_case() {
  return {
      Field::number("cell", "m", "Grid cell size, also the membrane element size (paper: 1 mm).")
          .at_least(0.25e-3).at_most(10e-3).def(1e-3),
      Field::number("particle_spacing", "m", "Spacing of the particle lattice of the sphere, cell / n with n = 1 to 4 (paper: 0.5 mm).")
          .greater(0).def(0.5e-3),
      Field::number("mpm_cfl", "", "Safety factor on the critical MPM step of eq. (21).")
          .greater(0).at_most(1).def(0.5),
  };
}

}  // namespace

Field mpm() {
  return Field::object("mpm",
                       "MPM particles in contact with Belytschko-Tsay membranes on the background grid "
                       "(Lian, Liu & Zhang 2014). Run by the `mpm` runner; the scene then has no "
                       "`fluid` and no `solids`, and `simulation.gravity`, `simulation.cfl` are not used "
                       "(the examples have no gravity; each has its own CFL key). `simulation.end_time` "
                       "is the end time; frames follow `simulation.frame_rate`.", {
      Field::enumeration("example", {"gas_expansion", "membrane_on_sphere", "sphere_on_membrane",
                                     "water_sphere_impact"},
                         "`gas_expansion` (7.3): ideal gas block expanding in a rectangular membrane, quarter "
                         "model, dimensionless units (end time 4); `membrane_on_sphere` (7.1): a 50 mm membrane "
                         "falling at 50 m/s on a fixed elastic sphere; `sphere_on_membrane` (7.1): an elastic "
                         "sphere at 10 m/s hitting a clamped membrane; `water_sphere_impact` (7.2): a water "
                         "sphere (Mie-Grueneisen) at 10 m/s hitting a soft clamped membrane. Sphere cases: "
                         "end time about 0.4 ms.").req(),
      contact(),
      Field::integer("stats_rows_per_frame",
                     "Rows of stats.csv and probes.csv per output frame. Each row holds the exact state at "
                     "its time; the coupled steps between rows (often thousands: the explicit step is "
                     "limited by the critical step of section 4.4) are not written.")
          .at_least(1).at_most(1000).def(1),
  }).tagged_by("example")
    .variant("gas_expansion", {
        Field::number("cell", "", "Grid cell size, also the membrane element size (paper: 0.1).")
            .at_least(0.01).at_most(0.25).def(0.1),
        Field::number("particle_spacing", "", "Spacing of the gas particle lattice, cell / n with n = 1 to 4 (paper: 0.025).")
            .greater(0).def(0.025),
        Field::number("cfl", "", "Time step as a fraction of the membrane's critical step min(L_e / c) "
                      "(eq. 48 has no safety factor; 0.9 is tetfsi's).")
            .greater(0).at_most(1).def(0.9),
        Field::number("gas_viscosity", "", "Shear viscosity of the gas (Table 2: 0.1).").at_least(0).def(0.1),
        Field::number("hourglass", "", "Flanagan-Belytschko hourglass coefficient of the membrane.")
            .at_least(0).at_most(1).def(0.1)})
    .variant("membrane_on_sphere", sphere_case())
    .variant("sphere_on_membrane", sphere_case())
    .variant("water_sphere_impact", sphere_case())
    .check(spacing_fits_cell);
}

}  // namespace tetfsi::scene::blocks
