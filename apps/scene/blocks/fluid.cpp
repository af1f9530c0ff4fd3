#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {
namespace {

Field solver() {
  return Field::object("solver", "Linear solver of the pressure (or coupled) system.", {
      Field::enumeration("type", {"amg", "ic", "petsc"},
                         "Preconditioner: `amg` (hypre BoomerAMG, this process), `ic` (incomplete Cholesky) or "
                         "`petsc` (PETSc CG with BoomerAMG, the rows spread over the processes of `mpirun -n N "
                         "tetfsi run`; required with more than one process; docs/scaling.md).")
          .def("amg"),
      Field::number("tolerance", "", "Relative residual at which the solver stops.")
          .greater(0).less(1).def(1e-6),
      Field::integer("max_iterations", "Iteration limit; reaching it is reported as a failure.")
          .at_least(1).def(500),
  });
}

Field density(double def) {
  return Field::number("density", "kg/m^3", "Mass density of the fluid.").greater(0).def(def);
}

Field viscosity(double def) {
  return Field::number("viscosity", "Pa s",
                       "Dynamic viscosity mu; > 0: an implicit viscous step each step (backward Euler, stable "
                       "for any value and step; fluid/README.md, \"Viscosity\"); 0: inviscid.")
      .at_least(0).at_most(1e9).def(def);
}

/// Boxes of other viscosity (a paint stripe in water, a honey layer).
Field viscosity_regions() {
  Field region = Field::object("", "", {
      Field::vector("lo", 3, "m", "Lower corner.").req(),
      Field::vector("hi", 3, "m", "Upper corner.").req(),
      Field::number("viscosity", "Pa s", "Dynamic viscosity of the fluid in the box.").req().at_least(0).at_most(1e9)})
      .check(lo_below_hi());
  return Field::array("viscosity_regions",
                      "Regions of other viscosity: a tet whose centroid lies in [lo, hi] has this viscosity "
                      "instead of `viscosity` (first match wins; the boxes stay fixed in space).",
                      std::move(region))
      .def(Json::array());
}

Field walls() {
  return Field::enumeration("walls", {"no_slip", "slip"},
                            "Tangential condition of the container walls and solid surfaces when the fluid is "
                            "viscous: `no_slip` (the fluid sticks: velocity of the wall or solid) or `slip` (no "
                            "tangential stress). Inflow patches and `domain.moving_walls` always prescribe their "
                            "velocity; open faces carry no viscous stress. Inviscid fluids slip either way.")
      .def("no_slip");
}

Field advection(const char* def) {
  return Field::enumeration("advection", {"linear", "semi_lagrangian", "bfecc", "apic", "flip"},
                            "How the velocity is carried across meshes. On the mesh "
                            "(fluid/advection/semi_lagrangian.hpp): `linear` (tet-wise linear reconstruction), "
                            "`semi_lagrangian` (plain back-trace), `bfecc` (error-compensated). On particles "
                            "(fluid/particles/particles.hpp; fluid/README.md, \"Particles\"): `apic` (affine "
                            "particle-in-cell, Jiang et al. 2015), `flip` (FLIP/PIC blend, Zhu & Bridson 2005, with "
                            "`flip_ratio`); smoke and temperature stay on the mesh (`linear`).")
      .def(def);
}

Field flip_ratio() {
  return Field::number("flip_ratio", "",
                       "With `advection: flip`: the FLIP share r of the particles' new velocity, (1 - r) PIC + r "
                       "FLIP; 0: PIC (dissipative), 1: pure FLIP (noisy).")
      .at_least(0).at_most(1).def(0.97);
}

Field particles_per_tet() {
  return Field::integer("particles_per_tet",
                        "With `advection: apic` or `flip`: particles aimed at per tet full of fluid (a liquid's cut "
                        "tets: times their liquid fraction); reseeding keeps each tet within 2/3 to 4/3 of it.")
      .at_least(1).def(6);
}

Field apply_gravity(bool def) {
  return Field::boolean("apply_gravity",
                        "Add `simulation.gravity` to the fluid velocity (for smoke it only adds a "
                        "hydrostatic pressure; buoyancy acts either way).")
      .def(def);
}

Field remesh_band() {
  return Field::number("remesh_band", "m",
                       "With moving (kinematic) solids the fluid moves with them every step and is remeshed "
                       "when the moved mesh degrades (stats column remeshed); > 0: only fluid tets within "
                       "this distance of the degraded tets; 0: the whole fluid.")
      .at_least(0).def(0);
}

/// Initial liquid of `fill: regions`: one shape each; the liquid is their union.
Field liquid_regions() {
  Field region = Field::object("", "", {
      Field::enumeration("type", {"box", "sphere", "below", "mesh"},
                         "`box`: [lo, hi]; `sphere`: centre and radius; `below`: everything whose height "
                         "(the coordinate along -simulation.gravity) is below `height`; `mesh`: the inside of a "
                         "closed surface file (OBJ, PLY, STL, glTF, FBX, OFF), placed like a solid's.").req()})
      .tagged_by("type")
      .variant("box", {Field::vector("lo", 3, "m", "Lower corner.").req(),
                       Field::vector("hi", 3, "m", "Upper corner.").req()})
      .variant("sphere", {Field::vector("center", 3, "m", "Centre.").req(),
                          Field::number("radius", "m", "Radius.").req().greater(0),
                          Field::number("cap_height", "m",
                                        "If given: only the part of the sphere below this height (along "
                                        "-gravity, from the origin), e.g. a bowl filled to a level.")})
      .variant("below", {Field::number("height", "m", "Height of the still surface (along -gravity, from the "
                                                       "origin).").req()})
      .variant("mesh", {Field::file("file", "Closed surface file, relative to the scene file's folder.").req(),
                        Field::number("unit_scale", "m/unit", "Metres per file unit (0.01 for files in cm).")
                            .greater(0).def(1.0),
                        Field::vector("rotation_deg", 3, "deg", "Euler XYZ rotation (about x, then y, then z), after the "
                                                                "scale.").def({0, 0, 0}),
                        Field::vector("translation", 3, "m", "Translation, applied last.").def({0, 0, 0})})
      .check(lo_below_hi());
  return Field::array("regions",
                      "With `fill: regions`: the liquid at t = 0, the union of these shapes (within the domain); "
                      "the rest of the domain is air, which is void (p = 0 on the free surface). A box's faces "
                      "that lie on the domain's walls are walls, not surface (a column may stand on the floor "
                      "against the walls). Each region must hold liquid: some of it inside the domain box, the "
                      "container and outside every solid.",
                      std::move(region))
      .def(Json::array());
}

}  // namespace

Field fluid() {
  return Field::object("fluid", "The fluid filling `domain`.", {
      Field::enumeration("type", {"none", "smoke", "liquid"},
                         "`none`: solids only; `smoke`: buoyant gas with density and temperature "
                         "fields; `liquid`: incompressible liquid.")
          .def("none"),
  }).tagged_by("type")
    .variant("none", {})
    .variant("smoke", {
        density(1.2), viscosity(0.0), viscosity_regions(), walls(),
        Field::number("buoyancy_alpha", "m/s^2",
                      "Downward force per unit smoke concentration (f = (-alpha s + beta (T - T_amb)) up).")
            .at_least(0).def(0.08),
        Field::number("buoyancy_beta", "m/(s^2 K)", "Upward force per kelvin above ambient.")
            .at_least(0).def(0.97),
        Field::number("ambient_temperature", "K", "Temperature of the surrounding air.").greater(0).def(293.15),
        Field::number("vorticity_confinement", "", "Strength of vorticity confinement; 0: off.")
            .at_least(0).def(0),
        advection("linear"), flip_ratio(), particles_per_tet(), apply_gravity(false), remesh_band(), solver()})
    .variant("liquid", {density(1000), viscosity(1e-3), viscosity_regions(), walls(), advection("linear"), flip_ratio(),
                        particles_per_tet(), apply_gravity(true), remesh_band(),
                        solver(),
                        Field::enumeration("fill", {"domain", "cavities", "regions"},
                                           "`domain`: the liquid fills the domain box around the solids "
                                           "and the cavities of `sphere_shell` solids; `cavities`: only the "
                                           "cavity of the scene's one `sphere_shell` (a liquid-filled toy "
                                           "with nothing outside; no domain box); `regions`: the liquid "
                                           "fills `regions` and has a free surface; it couples two-way with "
                                           "deforming `tet_fem` solids as well as static and kinematic ones (a "
                                           "free `hex8` solid and `coupling.constraint` `step_mean` are "
                                           "refused).")
                            .def("domain"),
                        liquid_regions(),
                        Field::number("surface_edge_length", "m",
                                      "With `fill: regions`: target edge length of the mesh within three of it "
                                      "of the liquid surface, graded to `mesh.edge_length` over "
                                      "max(`mesh.grading_distance`, three of it); when the surface leaves the refined "
                                      "zone, the fluid is remeshed where the mesh no longer fits (fluid and coupled "
                                      "runners). 0: a mesh that ignores the surface.")
                            .at_least(0).def(0),
                        Field::enumeration("level_set_advection", {"bfecc", "semi_lagrangian"},
                                           "With `fill: regions`: how the liquid's level set is carried each step. "
                                           "`bfecc`: back-and-forth error compensation (Dupont & Liu 2003), which "
                                           "keeps thin sheets and drops far longer; `semi_lagrangian`: first-order "
                                           "interpolation (half the cost of the level-set advection).")
                            .def("semi_lagrangian")});
}

}  // namespace tetfsi::scene::blocks
