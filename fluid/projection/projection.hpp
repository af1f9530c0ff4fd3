#pragma once
/// @file projection.hpp
/// Pressure projection of the nodal-pressure / tet-velocity scheme (Ando et al. 2013, sec. 3):
///
///   (h/rho) L p = G^T V u* - f     at every node that is not open (p = 0 at open nodes)
///   u_t = u*_t - (h/rho) (G p)_t
///
/// with L = G^T V G, f the prescribed boundary flux (boundary_flux.hpp). After the solve the weak
/// divergence (D u)_i = -(G^T V u)_i + f_i equals minus the linear-system residual, so it is zero to
/// solver tolerance. The update is the V-orthogonal projection onto weakly divergence-free fields:
/// it never adds kinetic energy. This is the fluid row of Chentanez et al. 2006 eq. (6) with D = -G^T V.
///
/// Closed domains (no open node) have the constant null space. We remove the mean of the right-hand
/// side (after checking that the net boundary inflow is zero), pin the lowest-index node to p = 0 and
/// solve the rest; the pinned equation then holds too because all equations sum to zero. Finally the
/// pressure is shifted to zero dual-volume-weighted mean (the gauge of a closed domain).
#include <Eigen/Core>

#include "fluid/boundary/boundary_conditions.hpp"
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/projection/linear_solver.hpp"

namespace tetfsi::fluid {

struct ProjectionReport {
  Eigen::VectorXd pressure;        ///< per fluid node [Pa]
  SolveReport solve;
  int unknowns = 0;
  double assemble_seconds = 0.0;   ///< building L and the right-hand side
  double solve_seconds = 0.0;      ///< set-up + iterations
  double max_divergence = 0.0;     ///< max over non-open nodes of |(D u)_i| / dual_volume_i [1/s]
};

/// Weak divergence (D u)_i = -(G^T V u)_i + f_i [m^3/s] at every node.
Eigen::VectorXd weak_divergence(const FluidMesh& mesh, const ClassifiedBoundary& bc, const TetVectors& u);

/// max over non-open nodes of |(D u)_i| / dual_volume_i [1/s].
double max_normalized_divergence(const FluidMesh& mesh, const ClassifiedBoundary& bc, const TetVectors& u);

/// Solves a x = b on the m unknowns, b gathered from the per-node `rhs` (node i is unknown[i], or
/// not an unknown if < 0), and scatters x into rep.pressure (zero at the other nodes); fills
/// rep.unknowns, rep.solve and rep.solve_seconds. Shared by project() and project_free_surface().
/// @throws SolverError if the solve fails
void solve_on_unknowns(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& rhs, const std::vector<int>& unknown,
                       int m, const SolverOptions& options, ProjectionReport& rep);

/// Projects u in place (see file doc).
/// @param h        time step [s], > 0
/// @param density  rho [kg/m^3], > 0
/// @throws std::invalid_argument on non-positive h/density, or net inflow into a closed domain
/// @throws SolverError if the pressure solve fails
ProjectionReport project(const FluidMesh& mesh, const ClassifiedBoundary& bc, double h, double density,
                         TetVectors& u, const SolverOptions& options);

}  // namespace tetfsi::fluid
