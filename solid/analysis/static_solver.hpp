#pragma once
/// @file static_solver.hpp
/// Quasi-static equilibrium of a solid (any ElasticModel: tet or hex8) by load stepping with
/// Newton-Raphson (Bathe 1996, *Finite Element Procedures*, sec. 8.4.1):
///   K_T Delta u_f = R = lambda (F_ext + F_p(u)) - F_int(u)  on the free dofs,
/// after moving the prescribed dofs to the right-hand side (partitioned: K_ff u_f = -K_fs u_s).
/// F_ext are the dead loads, F_p the follower pressure (solid/loads/follower_pressure.hpp), whose
/// load stiffness -lambda dF_p/du enters K_T: the tangent is then the consistent, non-symmetric
/// one and the solves use Eigen's SparseLU instead of Cholesky or CG, whatever `linear_solver`
/// says (quadratic convergence is kept).
///
/// Constraints are written as u = T q + g(lambda): q are the unknowns (free dofs plus the 3
/// translations of each RotatingFace), g the prescribed part. T only selects/sums dofs, so
/// T^T K T is K_ff with the rows/columns of a rigid face summed. A load step from lambda_0 to
/// lambda_1 starts with the seed's predictor
///   (T^T K_T T) Delta q = T^T (R(u) - K_T Delta g),   Delta g = g(lambda_1) - g(lambda_0),
/// (= K_ff Delta u_f = -K_fs Delta u_s at equilibrium) and then iterates
///   (T^T K_T T) Delta q = T^T R(u),  u <- u + T Delta q
/// until ||T^T R|| <= residual_tolerance * max(||lambda F_ext||, ||F_int - lambda F_p||) and
/// ||Delta q|| <= increment_tolerance * max(||u||, 1e-12 L) (L the mesh's bounding-box diagonal).
/// A failed step (inverted element, non-finite values, no convergence within max_iterations,
/// residual growing 1e6-fold, or a failed factorisation) is retried with half the load
/// increment, up to max_step_cuts times in a row; then NonConvergence is thrown.
/// Exact Newton: K_T is the model's exact tangent (ElasticModel::evaluate_exact) wherever T^T K_T T is
/// positive definite (the Cholesky factorisation succeeds), so that convergence is quadratic; where
/// it is not, and the model offers a modified tangent (the tets' per-element PSD projection,
/// TetModelOptions::project_spd), that one is assembled and solved instead for this iteration
/// (StepLog::modified_tangent_solves), as the dynamic step always does.
/// The linear solves use CHOLMOD's supernodal Cholesky (through Eigen::CholmodSupernodalLLT),
/// the pattern analysed once; if K_T is not positive definite there, Eigen::SimplicialLDLT.
/// The tangent's sparsity pattern is the one the model returns at u = 0.
/// Direct factorisation of a 3D block costs ~ dofs^2 flops (23 GFlop at 36k dofs), so large blocks
/// can use Eigen's Jacobi-preconditioned CG instead (LinearSolverKind).
#include <Eigen/Core>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "solid/elastic_model.hpp"
#include "solid/loads/boundary_conditions.hpp"

namespace tetfsi::solid {

/// Linear solver for the Newton systems.
enum class LinearSolverKind {
  Cholmod,            ///< CHOLMOD supernodal Cholesky (SimplicialLDLT if K_T is indefinite; SparseLU with
                      ///< follower pressure): exact, default
  ConjugateGradient,  ///< Eigen CG with Jacobi preconditioner: for large 3D blocks
};

struct StaticOptions {
  int load_steps = 10;               ///< nominal number of equal load increments to lambda = 1
  int max_iterations = 30;           ///< Newton iterations per step before the step is cut
  double residual_tolerance = 1e-9;  ///< relative, see the file comment
  double increment_tolerance = 1e-8; ///< relative, see the file comment
  int max_step_cuts = 8;             ///< successive halvings of one increment before giving up
  /// Load-step attempts (converged or cut) before giving up, so that a hopeless problem cannot
  /// crawl on with tiny increments; 0 = 10 load_steps + 2 max_step_cuts + 10.
  int max_step_attempts = 0;
  LinearSolverKind linear_solver = LinearSolverKind::Cholmod;
  double cg_tolerance = 1e-10;       ///< relative residual of each CG solve
  int cg_max_iterations = 5000;
  bool log = false;                  ///< print each iteration's residual ratio (spdlog, info)
};

struct StepLog;
/// Called after each converged load step with its log and the displacement [m].
using StepCallback = std::function<void(const StepLog&, const Eigen::VectorXd&)>;

/// One converged load step.
struct StepLog {
  double load_factor = 0.0;        ///< lambda reached
  int iterations = 0;              ///< linear solves in this step (predictor included)
  std::vector<double> residuals;   ///< ||T^T R|| / reference after each solve
  int cuts = 0;                    ///< halvings needed before this step converged
  int modified_tangent_solves = 0; ///< solves with the model's modified tangent (exact one not PD)
};

struct StaticResult {
  Eigen::VectorXd displacement;              ///< u at lambda = 1 [m]
  std::vector<StepLog> steps;
  /// Per RotatingFace: net force (~0) [N] and moment about its current centroid [N m] that the
  /// constraint applies to the body (= sum over its nodes of F_int and (x - x_c) x F_int).
  std::vector<Eigen::Vector3d> face_forces, face_moments;
  int total_iterations = 0;
  int cg_iterations = 0;                     ///< total CG iterations (ConjugateGradient only)
  double assembly_seconds = 0.0, solve_seconds = 0.0;
};

/// Thrown when a load step cannot converge even after max_step_cuts halvings.
class NonConvergence : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Solves the static problem from u = 0 to lambda = final_load_factor in options.load_steps steps.
/// @throws std::invalid_argument for inconsistent boundary conditions (a dof constrained twice,
///         out-of-range dofs, a force vector of the wrong size, no constraint against rigid motion
///         is not detected here but shows up as a failed factorisation -> NonConvergence)
/// @throws NonConvergence with the load factor, the cause and the last residuals
StaticResult solve_static(const ElasticModel& model, const BoundaryConditions& bc, const StaticOptions& options = {},
                          double final_load_factor = 1.0, const StepCallback& on_step = {});

/// Net force [N] and moment about its current centroid [N m] that the constraint of `face` applies
/// to the body at displacement u: sum over its nodes of F_int and (x - x_c) x F_int (at
/// equilibrium the constrained nodes carry no other load).
void face_reaction(const ElasticModel& model, const RotatingFace& face, const Eigen::VectorXd& u,
                   Eigen::Vector3d& force, Eigen::Vector3d& moment);

}  // namespace tetfsi::solid
