#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {

Field coupling() {
  return Field::object("coupling",
                       "How a fluid and deformable solids are advanced together (coupling/README.md). Used "
                       "by scenes with a fluid and deformable tet solids (all keys have defaults).", {
      Field::enumeration("scheme", {"simultaneous", "time_splitting"},
                         "`simultaneous`: one linear system for fluid pressure and solid velocities "
                         "(Chentanez et al. 2006, eq. 7); `time_splitting`: solid with the previous "
                         "pressure, then fluid with the new solid velocity (a baseline; unstable when "
                         "the fluid's added mass exceeds the solid's mass).")
          .def("simultaneous"),
      Field::enumeration("solver", {"schur_cg", "bicgstab", "umfpack"},
                         "Solver of eq. (7): `schur_cg` (CG on the pressure Schur complement, the fast "
                         "path), `bicgstab` (as in the paper), `umfpack` (direct LU, the reference).")
          .def("schur_cg"),
      Field::boolean("reuse_factorization",
                     "`schur_cg` only: keep the solid block's Cholesky factor and the pressure "
                     "preconditioner from an earlier step and solve by GMRES preconditioned with them "
                     "(`solver_factor_age` > 0 in stats.csv), refactorizing the solid block once the "
                     "extra iterations its drift costs add up to half a fresh solve and rebuilding both once "
                     "they add up to two; the answer meets the same tolerance. `false` factorizes every step.")
          .def(true),
      Field::number("tolerance", "", "Relative residual of each block row at which the solve stops.")
          .greater(0).less(1).def(1e-8),
      Field::integer("max_iterations", "Iteration limit of the iterative solvers; reaching it stops the run.")
          .at_least(1).def(2000),
      Field::enumeration("newmark", {"chentanez", "trapezoidal"},
                         "Solid time integration: eq. (18) as printed in the paper (Newmark beta = 1/2, "
                         "gamma = 1, slightly dissipative) or the energy-conserving trapezoidal rule "
                         "(beta = 1/4, gamma = 1/2).")
          .def("chentanez"),
      Field::enumeration("constraint", {"step_mean", "end_of_step"},
                         "Incompressibility constraint of the simultaneous solve: `end_of_step` as printed "
                         "in eq. (7); `step_mean` on the step's mean fluid and solid velocities with the "
                         "interface at mid-step, which keeps a closed cavity's volume to O(h^3) per step "
                         "instead of O(h^2) (use it for liquid-filled shells) but lets divergence errors "
                         "alternate in sign from step to step, which diverged on the open-jet bar scene "
                         "(coupling/README.md).")
          .def("end_of_step"),
      Field::boolean("keep_closed_volumes",
                     "Simultaneous scheme: every closed fluid region (no open face, inflow or free surface) "
                     "bounded by moving solids keeps its volume: the solids' start-of-step velocity is "
                     "projected onto the velocities that keep it and the step's constraint carries the "
                     "volume left to restore (coupling/closed_regions.hpp; stats.csv `closed_volume_error`, "
                     "`closed_volume_correction`). `false`: eq. (7) alone, whose region volumes drift "
                     "by O(h^2) a step and more in contact.")
          .def(true),
      Field::enumeration("mesh_update", {"remesh_when_needed", "remesh_every_step", "move"},
                         "How the fluid mesh follows the solids each step: the fluid vertices always "
                         "follow (stiffened Laplacian of the solid motion); `remesh_when_needed` remeshes "
                         "the fluid with CGAL when its minimum dihedral angle falls below "
                         "`remesh_below_deg`, `remesh_every_step` every step (as in the paper), `move` "
                         "never. Only the fluid within `fluid.remesh_band` of the tets that fell below the "
                         "threshold is remeshed (0: four near-solid cell sizes).")
          .def("remesh_when_needed"),
      Field::number("remesh_below_deg", "deg",
                    "With `remesh_when_needed`: remesh when the moved fluid's minimum dihedral angle is "
                    "below this (or below half the angle before the step, if that is smaller).")
          .greater(0).less(60).def(10),
      Field::enumeration("mesh_motion_solver", {"auto", "cholesky", "amg"},
                         "How the stiffened Laplacian that moves the fluid vertices with the solids is solved "
                         "each step. `cholesky`: factorized once per mesh (CHOLMOD), then two triangular solves "
                         "a step; the factorization takes seconds at a million fluid tets and its factor is the "
                         "largest item in memory. `amg`: conjugate gradients with a BoomerAMG V-cycle from the "
                         "extrapolated motion of the last two steps, to 1e-3 of that guess's residual; no "
                         "factorization and no factor, at about twice the per-step cost of the factor's "
                         "solves (docs/scaling.md has both measured). `auto`: `cholesky` up to 500,000 "
                         "fluid tets, `amg` above (where the factor would be the largest item in memory).")
          .def("auto"),
      Field::boolean("wall_contact",
                     "The container's walls are contact obstacles for every solid (the container's faces, "
                     "set back by `contact_gap`), so a solid that sinks, rises or is thrown comes to rest on "
                     "the floor, the lid or a side with a film of fluid of that thickness between; the "
                     "contact is part of the simultaneous solve, with `obstacles.friction`. "
                     "`false`: solids that reach a wall stop the run.")
          .def(true),
      Field::boolean("solid_contact",
                     "Deformable solids touch each other through the fluid: a surface node of one solid "
                     "and the nearest surface triangle of another keep a film of `contact_gap` between "
                     "them (node-to-surface penalty constraints in the simultaneous solve, momentum "
                     "conserving, Coulomb friction from `obstacles.friction`; solid/contact/surface_contact.hpp). "
                     "Kinematic and fixed parts are obstacles for the others. `false`: solids that meet stop the run.")
          .def(true),
      Field::enumeration_set("compare_solvers", {"bicgstab", "umfpack", "projection"},
                             "Benchmark: after each step's solve, solve the same system again from the same "
                             "guess with these and record their wall time and iterations in stats.csv "
                             "(`compare_<name>_seconds`, `compare_<name>_iterations`); the answers are discarded, "
                             "so the run is unchanged. `bicgstab`, `umfpack`: eq. (7) by that solver; "
                             "`projection`: the fluid-only pressure projection of the same mesh (the solids as "
                             "walls) by `fluid.solver`. `umfpack` needs several GB beyond ~300k unknowns.")
          .def(Json::array()),
      Field::number("contact_gap", "m",
                    "Thickness of the fluid film kept between a solid and the container's walls "
                    "(`wall_contact`), the obstacles, another solid (`solid_contact`) or itself "
                    "(`/solids/*/self_contact`); 0: half the fluid's edge length next to the solids as meshed.")
          .at_least(0).def(0),
  });
}

}  // namespace tetfsi::scene::blocks
