#pragma once
/// @file sphere_membrane.hpp
/// Lian, Liu & Zhang (2014) sections 7.1 and 7.2 (SI units; the paper gives mm, MPa, g/mm^3):
///  - MembraneOnSphere (7.1, Figs. 5-7): a 50 x 50 mm membrane (t = 0.1 mm, E = 1e10 Pa,
///    nu = 0.3, rho = 750) at z = 31 mm falls at 50 m/s onto an elastic MPM sphere (R = 15 mm,
///    centre (0, 0, 15) mm, E = 7e10 Pa, nu = 0.3, rho = 2750) whose bottom is fixed (grid floor
///    at z = 0). Probes (Fig. 6): z of the membrane centre and of the corner (-25, -25) mm.
///  - SphereOnMembrane (7.1, Figs. 8-11): an elastic sphere (R = 4.5 mm, centre (0, 0, 5.5) mm,
///    10 m/s down) hits a membrane clamped on its four sides at z = 0; both E = 7e10, nu = 0.3,
///    rho = 750. Probes (Fig. 9, 11): z of the membrane centre and of the sphere top (0, 0, 10) mm.
///  - WaterSphere (7.2, Figs. 12-13): the same with a water sphere (Mie-Grueneisen, Table 1,
///    centre (0, 0, 5.0) mm so the gap is 0.5 mm) and a soft membrane (E = 6e4 Pa, rho = 750).
/// Defaults: cell and element size 1 mm, particle spacing 0.5 mm (the paper's).
#include <functional>

#include "coupling/mpm/examples/step_record.hpp"

namespace tetfsi::mpm_contact {

struct SphereMembraneParams {
  enum class Case { MembraneOnSphere, SphereOnMembrane, WaterSphere };
  Case which = Case::SphereOnMembrane;
  double cell = 1e-3;              ///< grid cell and membrane element size [m]
  double particle_spacing = 0.5e-3;  ///< [m]
  double t_end = 0.4e-3;           ///< [s]
  double mpm_cfl = 0.5;
  ContactOptions contact{};
  int record_every = 100;
};

struct SphereMembraneResult {
  long steps = 0;
  long particle_updates = 0;
  std::size_t particles = 0;
  int elements = 0;
  double membrane_center_z = 0;  ///< final [m]
  double min_membrane_center_z = 0;
  double second_probe_z = 0;  ///< final corner z (7.1a) or sphere top z (7.1b, 7.2) [m]
  /// Stored energy (kinetic + internal of both bodies, membrane hourglass) at start and end [J].
  double energy_initial = 0, energy_final = 0;
  double contact_dissipated = 0;  ///< accumulated work removed by the contact forces [J]
};

/// @throws std::invalid_argument on bad sizes, std::runtime_error on instability
SphereMembraneResult run_sphere_membrane(const SphereMembraneParams& params,
                                         const std::function<void(const StepRecord&)>& on_record = nullptr);

}  // namespace tetfsi::mpm_contact
