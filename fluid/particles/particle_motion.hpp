#pragma once
/// @file particle_motion.hpp
/// Moving the particles from one mesh to the next (particles.hpp, steps 1): through the old mesh's
/// velocity, then found in the new mesh, kept inside the fluid (off walls and solids) and inside
/// the liquid (phi < 0).
#include <vector>

#include <Eigen/Core>

#include "fluid/advection/point_locator.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/particles/particles.hpp"

namespace tetfsi::fluid {

/// Moves every particle over h [s] by the explicit midpoint rule (RK2),
///   x_mid = x_p + (h/2) v̄(x_p),   x_p <- x_p + h v̄(x_mid),
/// through v̄, the P1 interpolant of the node averages of `velocity` on old_mesh with the tet
/// weights `weight` (nullptr: volumes): the field that carries a liquid's level set (advect_nodal),
/// so that particles and surface move together. A point outside the old fluid reads v̄ at the
/// boundary tet nearest it (clamped barycentric coordinates). The particles' `tet` must be tets of
/// old_mesh; it is left pointing at the tet of the last midpoint (a hint, no longer exact).
/// Deterministic; particles in parallel.
void advect_particles(const FluidMesh& old_mesh, const TetVectors& velocity, const std::vector<double>* weight,
                      const PointLocator& old_locator, double h, ParticleSet& particles);

/// Finds each particle in new_mesh and sets its `tet`. A particle outside the fluid (in a solid,
/// beyond a wall) moves to just inside the boundary tet nearest it: x̂ + 1e-3 (c_t - x̂), x̂ the
/// point of its clamped barycentric coordinates there. `old_to_new` (matching_tets(old, new), or
/// empty for a remeshed mesh) maps each particle's old tet to a start for the walk; without it the
/// walk starts at the previous particle's tet (particles sorted by old tet: close in space).
/// @return the number of particles moved back into the fluid. Sorts the particles by their new tet.
int locate_particles(const FluidMesh& new_mesh, const PointLocator& new_locator, const std::vector<int>& old_to_new,
                     ParticleSet& particles);

/// Keeps the particles strictly inside the liquid of the level set phi (nodal, on the particles'
/// mesh): a particle with phi(x_p) >= 0 within one mean edge of the surface moves along the
/// surface normal to phi = -0.05 mean edge, x_p <- x_p - (phi + 0.05 dx) ∇phi / |∇phi|^2 (∇phi of
/// its tet, up to three times as it crosses tets); the others and those still outside are deleted.
/// @return {moved, deleted}. Keeps the particles sorted by tet.
std::pair<int, int> keep_in_liquid(const FluidMesh& mesh, const PointLocator& locator, const Eigen::VectorXd& phi,
                                   ParticleSet& particles);

/// phi at x in tet t (P1 interpolation).
double level_set_at(const FluidMesh& mesh, const Eigen::VectorXd& phi, int t, const Eigen::Vector3d& x);

}  // namespace tetfsi::fluid
