#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {

Field coupling() {
  return Field::object("coupling",
                       "How a fluid and deformable solids are advanced together (coupling/README.md). A scene "
                       "with a fluid and deformable tet solids runs coupled only when it gives this "
                       "block (the coupled step does not remesh yet, so it suits small motions).", {
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
      Field::number("tolerance", "", "Relative residual of each block row at which the solve stops.")
          .greater(0).less(1).def(1e-8),
      Field::integer("max_iterations", "Iteration limit of the iterative solvers; reaching it stops the run.")
          .at_least(1).def(2000),
      Field::enumeration("newmark", {"chentanez", "trapezoidal"},
                         "Solid time integration: eq. (18) as printed in the paper (Newmark beta = 1/2, "
                         "gamma = 1, slightly dissipative) or the energy-conserving trapezoidal rule "
                         "(beta = 1/4, gamma = 1/2).")
          .def("chentanez"),
  });
}

}  // namespace tetfsi::scene::blocks
