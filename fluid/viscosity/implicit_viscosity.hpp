#pragma once
/// @file implicit_viscosity.hpp
/// Implicit (backward Euler) viscosity of the nodal-pressure / tet-velocity fluid, solved after the
/// advection and before the body forces and the projection, unconditionally stable for any viscosity and step, as
/// Batty & Bridson (2008, "Accurate viscous free surfaces for buckling, coiling, and rotating
/// liquids", eq. 3) solve it for liquids:
///
///   rho (u^{n+1} - u*) / h = div( 2 mu eps(u^{n+1}) ),   eps(u) = (grad u + grad u^T) / 2,
///
/// in the stress form, which keeps rigid rotations free of viscous forces (a spinning viscous blob
/// keeps spinning) and is right for a viscosity that varies from tet to tet.
///
/// Velocity space of the solve. The tet velocity is constant per tet: it has no gradient of its
/// own. The viscous problem is solved for P1 (nodal) velocities U, with the lumped mass
/// M_i = W_i / 4 (W_i = sum_{t ni i} w_t, w_t the tet's fluid volume: V_t, or |Omega_t| for a liquid
/// with a free surface) and the stress-form stiffness K,
///
///   (rho M + h K) dU = -h K U,     (K U)_i = sum_{t ni i} w_t 2 mu_t eps_t(U) grad(phi_i)|_t,
///
/// for the increment dU, with dU = 0 at the Dirichlet nodes (viscous_boundary.hpp; U there is the
/// prescribed velocity). U_i is the value at x_i of a least-squares quadratic fit q_i of the tet
/// velocities around node i (node_fit.hpp): exact for linear and quadratic fields on any mesh; the
/// weighted average is not even exact for linear fields there, and K of its O(dx) mesh noise is
/// an O(1/dx) error in the viscous force. Each tet then takes the nodal increment, and its sub-cell
/// fluctuation about its smooth reference decays as the finest mode the tet can hold:
///   u_t <- u_t + (P dU)_t - (1 - beta_t) (u_t - r_t),   (P dU)_t = (1/4) sum_k dU_{t_k},
///   r_t = (1/4) sum_k q_{t_k}(c_t),   beta_t = 1 / (1 + h nu_t sum_k |grad phi_k|^2_t),  nu_t = mu_t / rho.
/// For mu -> 0 (beta -> 1) u only receives P dU -> 0: no smoothing of a round trip tets -> nodes
/// -> tets (which would act as a numerical viscosity of order dx^2 / h every step). For a strongly
/// viscous step (beta -> 0) no tet keeps a velocity the nodal problem cannot see: without the
/// decay, a body force on a tet whose four nodes are no-slip accelerates it without bound (plane
/// Poiseuille flow ran away so). The reference r_t is the fits' value at the centroid, not the
/// mean of the nodal values: for a smooth field u_t - (1/4) sum U_{t_k} is O(dx^2) D^2 u, and
/// damping that at the rate nu / dx^2 added an O(1) error to the viscosity (a shear wave decayed
/// 4% too fast at every resolution); u_t - r_t is O(dx^3) (0.1% at 12 cells per half wave).
/// Linear fields (Couette flow) and rigid rotations are steady exactly (K U = 0 at the free nodes
/// for any linear U on any mesh, sum_t V_t grad(phi_i) = 0 at an interior node; the stress of a
/// rotation is 0; u = r then).
/// Stability: the nodal problem is backward Euler (unconditionally stable, dissipative for walls
/// at rest); the update of the tets is not proven dissipative (the fits are not the adjoint of P),
/// test_viscosity.cpp checks it on random fields for h mu / (rho dx^2) from 1e-7 to 1e5.
/// The product K U is formed per tet (eps_t) and gathered per node, never assembled (no memory
/// beyond a few nodal vectors); CG with the Jacobi preconditioner solves the system, whose
/// condition number is about 1 + c h mu / (rho dx^2): a few iterations for water.
#include <Eigen/Core>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/projection/linear_solver.hpp"
#include "fluid/viscosity/viscous_boundary.hpp"

namespace tetfsi::fluid {

struct ViscosityReport {
  int iterations = 0;
  double relative_residual = 0.0;  ///< ||b - A dU|| / ||b|| of the increment's system
  double seconds = 0.0;
  /// Per fluid node: at the Dirichlet nodes, the force of the fluid's viscous stress on the wall or
  /// solid there, -(K U^{n+1})_i [N], the reaction that held the node (its sum is the fluid's
  /// momentum change over the step divided by -h: momentum is exchanged, not made); 0 elsewhere.
  std::vector<Eigen::Vector3d> wall_force;
  /// Per fluid node: at the Dirichlet nodes, the 3x3 diagonal block K_ii of the stiffness,
  /// sum_t w_t mu_t (|grad phi_i|^2 I + grad phi_i grad phi_i^T) [N s/m]: how wall_force falls as
  /// the node's own velocity rises with the fluid around it held (the coupled step's implicit
  /// drag, coupling/coupled_stepper.cpp); 0 elsewhere.
  std::vector<Eigen::Matrix3d> wall_stiffness;
};

/// One viscous step on the tet velocities `u` (in place).
/// @param viscosity per fluid tet dynamic viscosity mu_t [Pa s] (>= 0)
/// @param weight    per fluid tet fluid volume w_t [m^3] (V_t; |Omega_t| for a liquid; 0: no fluid)
/// @param density   rho [kg/m^3]
/// @param nodes     Dirichlet nodes and their velocity (viscous_nodes())
/// @param h         time step [s]
/// @param rings     node_rings(mesh) if the caller keeps it (node_fit.hpp); nullptr: made here
/// @throws SolverError if CG does not reach options.tolerance within options.max_iterations
ViscosityReport apply_viscosity(const FluidMesh& mesh, const std::vector<double>& viscosity,
                                const std::vector<double>& weight, double density, const ViscousNodes& nodes,
                                double h, const SolverOptions& options, TetVectors& u,
                                const std::vector<std::vector<int>>* rings = nullptr);

}  // namespace tetfsi::fluid
