#pragma once
/// @file trapezoidal.hpp
/// Trapezoidal-rule implicit Newmark integration with stiffness linearized at d^n
/// (Chentanez et al. 2006, sec. 3.2 and appendix, eqs. 9-18), generic over ElasticModel.
///
/// One step, solid alone (p = 0 in eq. 4):
///   A u^{n+1} = b,   A = M/h + C + (h/2) K',   C = alpha M + beta K'            (eq. 18)
///   b = (M/h) u^n - (h/2) K' u^n - K(d^n) + f_e                                 (eq. 18)
///   d^{n+1} = d^n + (h/2)(u^n + u^{n+1})                                        (eq. 5/12)
/// with K' = dK/dd at d^n, f_e = M g + nodal forces + spring forces. For a linear model this is
/// Newmark with beta = 1/4, gamma = 1/2 (energy conserving, period error ~ (omega h)^2/12).
///
/// The coupling uses the pieces: form_system() gives A and b at the current state (it then adds
/// -J p to the rows and solves together with the fluid), and advance() applies eq. (5) for a
/// given u^{n+1}, then contact, the Dirichlet values and the stability checks.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "solid/contact/static_obstacles.hpp"
#include "solid/elastic_model.hpp"
#include "solid/integrator/spd_solver.hpp"

namespace tetfsi::solid {

struct TrapezoidalSettings {
  double time_step = 1.0 / 30.0;                     ///< h [s]
  double rayleigh_alpha = 0.0;                       ///< C = alpha M + beta K' [1/s]
  double rayleigh_beta = 0.0;                        ///< [s]
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< [m/s^2]
  SolverKind solver = SolverKind::kCholmod;
  double cg_tolerance = 1e-10;     ///< relative residual for SolverKind::kConjugateGradient
  bool track_energy = true;        ///< fill the energy fields of StepStats (one extra pass)
};

/// Linear spring from a node to a fixed anchor: force -k (x - anchor) on the node.
struct LinearSpring {
  int node = 0;
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  ///< [m]
  double stiffness = 0;                              ///< k [N/m]
};

/// Per-step record (written to stats.csv by the runners).
struct StepStats {
  int step = 0;                 ///< index of the completed step (1 after the first)
  double time = 0;              ///< t^{n+1} [s]
  double assembly_seconds = 0;  ///< K(d), K', A and b
  double solve_seconds = 0;     ///< linear solve
  int solver_iterations = 0;
  double kinetic = 0;            ///< 1/2 u^T M u [J]
  double strain = 0;             ///< model strain energy [J]
  double gravity_potential = 0;  ///< -sum m g.x [J]
  double spring = 0;             ///< sum 1/2 k |x - anchor|^2 [J]
  double total() const { return kinetic + strain + gravity_potential + spring; }
  int inverted = 0;              ///< inverted elements at d^n (robust models)
  int contacts = 0;              ///< nodes projected out of obstacles
};

class TrapezoidalIntegrator {
 public:
  /// Starts at rest (d = u = 0, t = 0). The model must outlive the integrator.
  /// @throws SolidError on h <= 0 or negative damping
  TrapezoidalIntegrator(const ElasticModel& model, const TrapezoidalSettings& settings);

  // ---- set-up ----
  /// Dirichlet: the nodes' velocity is prescribed (default: fixed in place).
  void fix_nodes(const std::vector<int>& nodes, const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero());
  /// Nodes whose reference position lies in the box [lo, hi].
  std::vector<int> nodes_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
  void set_displacement(const Eigen::VectorXd& d);
  void set_velocity(const Eigen::VectorXd& u);
  void set_uniform_velocity(const Eigen::Vector3d& v);
  /// Constant external nodal forces, 3n [N] (added to M g).
  void set_external_forces(const Eigen::VectorXd& f);
  void add_spring(const LinearSpring& spring);
  StaticObstacles& obstacles() { return obstacles_; }

  // ---- pieces for the coupling ----
  /// A and b of eq. (4)/(18) at the current state. Dirichlet DOFs are eliminated
  /// symmetrically: their rows and columns are zero except the diagonal A_ii, b_i = A_ii v_i,
  /// and b of the other rows is corrected by -A_ij v_j. (The coupling must leave fixed rows
  /// out of J.) @throws SolidError naming the step and element if the model fails at d^n.
  void form_system(SparseMatrix& A, Eigen::VectorXd& b);
  /// Eq. (5) with the given u^{n+1}, then Dirichlet values, contact and finiteness checks;
  /// advances the time and step counter. @throws SolidError on non-finite values.
  void advance(const Eigen::VectorXd& u_next);

  // ---- whole step ----
  /// form_system + solve + advance. @throws SolidError (see above)
  const StepStats& step();

  // ---- state ----
  const Eigen::VectorXd& displacement() const { return d_; }
  const Eigen::VectorXd& velocity() const { return u_; }
  Eigen::VectorXd positions() const { return model_.reference_positions() + d_; }
  double time() const { return time_; }
  int step_index() const { return step_; }
  const std::vector<char>& fixed_dofs() const { return fixed_; }
  const StepStats& last_stats() const { return stats_; }
  const TrapezoidalSettings& settings() const { return settings_; }
  const ElasticModel& model() const { return model_; }
  /// Energies of the current state (fills the energy fields of a StepStats).
  StepStats energies() const;

 private:
  const ElasticModel& model_;
  TrapezoidalSettings settings_;
  Eigen::VectorXd d_, u_, f_ext_, prescribed_;
  std::vector<char> fixed_;
  std::vector<LinearSpring> springs_;
  StaticObstacles obstacles_;
  SpdSolver solver_;
  SparseMatrix K_tangent_, A_;
  Eigen::VectorXd K_force_, b_, u_next_;
  double time_ = 0;
  int step_ = 0;
  StepStats stats_;
};

}  // namespace tetfsi::solid
