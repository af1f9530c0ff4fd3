#pragma once
/// @file stable_step.hpp
/// The stable step of the fluid step on a tet mesh (the CFL condition), the one every caller that
/// chooses a fluid's step from its state uses (the fluid-only and the coupled runs).
#include "fluid/fluid_solver.hpp"

namespace tetfsi::fluid {

/// The CFL step [s]
///
///   h = min(h_max, C dx / u_max),   h = h_max when u_max = 0,
///
/// so that no semi-Lagrangian back-trace (semi_lagrangian.hpp) and no moving solid surface
/// crosses more than C cells of edge dx [m] in one step (the semi-Lagrangian advection itself is
/// stable beyond C = 1, fluid/README.md). C is the Courant number (scene key simulation.cfl),
/// h_max the longest step taken (one frame interval).
/// u_max [m/s] is the largest of
///   - the fluid's tet velocities max_t |v_t| (fluid.fields().velocity),
///   - `solid_speed`, the largest speed of the solids the fluid meets (0: none moves),
///   - with `free_fall` and a free surface, sqrt(|g| dx): the speed a liquid at rest reaches
///     falling over one cell, so that a liquid that starts at rest does not take h_max at once.
///     Without `free_fall` (the coupled runner) a liquid at rest and solids at rest give h_max.
double cfl_step(const FluidSolver& fluid, double courant, double dx, double solid_speed, double h_max,
                bool free_fall);

}  // namespace tetfsi::fluid
