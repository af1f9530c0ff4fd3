#pragma once
/// @file newmark.hpp
/// Implicit Newmark integration with stiffness linearized at d^n (Chentanez et al. 2006, sec. 3.2
/// and appendix, eqs. 9-18), generic over ElasticModel. By default the paper's Newmark beta = 1/2,
/// gamma = 1 (dissipative, not the trapezoidal rule); the trapezoidal rule is the other scheme.
///
/// One step, solid alone (p = 0 in eq. 4):
///   A u^{n+1} = b,   A = M/h + C + (h/2) K',   C = alpha M + beta K'            (eq. 18)
///   b = (M/h) u^n - (h/2) K' u^n - K(d^n) + f_e                                 (eq. 18)
///   d^{n+1} = d^n + (h/2)(u^n + u^{n+1})                                        (eq. 5/12)
/// with K' = dK/dd at d^n, f_e = M g + nodal forces + spring forces.
///
/// Note on the scheme. The appendix chooses Newmark beta = 1/2, gamma = 1 (eqs. 10-13): the
/// velocity update u^{n+1} = u^n + h a^{n+1} takes the force at d^{n+1}. That is NOT the
/// energy-conserving trapezoidal rule (beta = 1/4, gamma = 1/2; Newmark 1959; Hughes 2000, ch. 9): on
/// a linear undamped mode it multiplies the amplitude by 1/sqrt(1 + (omega h)^2 / 2) per step
/// (numerical damping ratio ~ omega h / 4 for small omega h). Both are offered, written with a
/// weight theta on the end-of-step forces,
///   M (u^{n+1} - u^n)/h = -[(1-theta) K(d^n) + theta K(d^{n+1})] - C[(1-theta) u^n + theta u^{n+1}] + f_e,
/// K(d^{n+1}) ~ K(d^n) + (h/2) K' (u^n + u^{n+1}) (eq. 16), giving
///   A = M/h + theta C + theta (h/2) K',
///   b = (M/h) u^n - theta (h/2) K' u^n - (1-theta) C u^n - K(d^n) + f_e:
/// theta = 1 is the paper's eq. (18) exactly (NewmarkScheme::kChentanez, the default);
/// theta = 1/2 is Newmark beta = 1/4, gamma = 1/2 (NewmarkScheme::kTrapezoidal), which for a
/// linear model conserves 1/2 u^T M u + 1/2 d^T K d and has T_bar/T = 1 + (omega h)^2/12.
/// Pressure forces J p^{n+1} enter with weight 1 in both (fully implicit constraint).
///
/// The coupling uses the pieces: form_system() gives A and b at the current state (it then adds
/// -J p to the rows and solves together with the fluid), and advance() applies eq. (5) for a
/// given u^{n+1}, then contact, the Dirichlet values and the stability checks.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "solid/contact/static_obstacles.hpp"
#include "solid/contact/surface_contact.hpp"
#include "solid/elastic_model.hpp"
#include "solid/integrator/spd_solver.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

namespace tetfsi::solid {

enum class NewmarkScheme {
  kChentanez,   ///< theta = 1: eqs. (9)-(18) as printed (Newmark beta = 1/2, gamma = 1)
  kTrapezoidal  ///< theta = 1/2: Newmark beta = 1/4, gamma = 1/2 (energy conserving)
};

/// Parses "chentanez" or "trapezoidal". @throws SolidError otherwise.
NewmarkScheme parse_newmark_scheme(const std::string& name);

struct NewmarkSettings {
  NewmarkScheme scheme = NewmarkScheme::kChentanez;
  double rayleigh_alpha = 0.0;                       ///< C = alpha M + beta K' [1/s]
  double rayleigh_beta = 0.0;                        ///< [s]
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< [m/s^2]
  SolverKind solver = SolverKind::kCholmod;
  double cg_tolerance = 1e-10;     ///< relative residual for SolverKind::kConjugateGradient
  bool track_energy = true;        ///< fill the energy fields of StepStats (one extra pass)
  /// Contact penalty κ of the active set as a multiple of the node's inertia m/h (not of A's
  /// diagonal, which a stiff solid's stiffness dominates): the constraint holds to about 1/κ of
  /// the node's change of momentum, and the solve's round-off grows with κ. (1e5 in the coupled
  /// step made a stiff ball at h = 1/120 s bounce for longer, so both runners use 1e7.)
  double contact_penalty = 1e7;
  /// ε_v [m/s] of the friction inside the solve (see step()): below this tangential speed a
  /// contact sticks (its friction force falls linearly to zero with the speed, as the smoothed
  /// Coulomb law of Li et al. 2020, IPC, sec. 5); it bounds the creep of a sticking node.
  double friction_velocity = 1e-3;
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

class NewmarkIntegrator {
 public:
  /// Starts at rest (d = u = 0, t = 0). The model must outlive the integrator.
  /// @throws SolidError on h <= 0 or negative damping
  NewmarkIntegrator(const ElasticModel& model, const NewmarkSettings& settings);

  // ---- set-up ----
  /// Dirichlet: the nodes' velocity is prescribed (default: fixed in place).
  void fix_nodes(const std::vector<int>& nodes, const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero());
  /// Dirichlet on some components only: component a of each node (x, y, z for a = 0, 1, 2) is
  /// prescribed where components[a] is true (velocity[a], default 0), the others stay free. A
  /// symmetry plane with normal e_a holds component a only. Nodes with any prescribed component
  /// take no part in obstacle contact (see step()).
  void fix_components(const std::vector<int>& nodes, const std::array<bool, 3>& components,
                      const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero());
  /// New prescribed velocity of node `node`'s fixed components (a driven or kinematic node whose
  /// velocity changes from step to step); its free components are left alone.
  void set_prescribed_velocity(int node, const Eigen::Vector3d& velocity) {
    for (int a = 0; a < 3; ++a)
      if (fixed_[3 * node + a]) prescribed_[3 * node + a] = u_[3 * node + a] = velocity[a];
  }
  /// Nodes whose reference position lies in the box [lo, hi].
  std::vector<int> nodes_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;
  void set_displacement(const Eigen::VectorXd& d);
  void set_velocity(const Eigen::VectorXd& u);
  void set_uniform_velocity(const Eigen::Vector3d& v);
  /// Constant external nodal forces, 3n [N] (added to M g).
  void set_external_forces(const Eigen::VectorXd& f);
  void add_spring(const LinearSpring& spring);
  StaticObstacles& obstacles() { return obstacles_; }
  /// Self-contact of the solid's surface inside step()'s implicit solve (solid/contact/surface_contact.hpp),
  /// keeping a film `gap` [m]; `tets` are the model's elements (node ids), friction Coulomb's μ.
  /// (The coupled step has its own, over all solids: coupling/coupled_stepper.hpp.)
  void enable_self_contact(const std::vector<std::array<int, 4>>& tets, double gap, double friction);

  // ---- pieces for the coupling ----
  /// A and b of eq. (4)/(18) at the current state for a step of length h [s] (see the scheme note above). Dirichlet DOFs are eliminated
  /// symmetrically: their rows and columns are zero except the diagonal A_ii, b_i = A_ii v_i,
  /// and b of the other rows is corrected by -A_ij v_j. (The coupling must leave fixed rows
  /// out of J.) @throws SolidError if h <= 0, naming the step and element if the model fails at d^n.
  void form_system(double h, SparseMatrix& A, Eigen::VectorXd& b);
  /// Eq. (5) over a step of length h [s] with the given u^{n+1} (end_displacement), then
  /// Dirichlet values, contact and finiteness checks; advances the time and step counter.
  /// @throws SolidError on non-finite values.
  void advance(double h, const Eigen::VectorXd& u_next);
  /// The displacement d^{n+1} that advance(h, u_next) sets: eq. (5), d + (h/2)(uⁿ + u^{n+1}).
  Eigen::VectorXd end_displacement(double h, const Eigen::VectorXd& u_next) const;

  // ---- contact with the obstacles when the caller owns the solve (the coupled step) ----
  // The same active set as step(): form_system, [warm_start_contacts], then rounds of
  //   solve (with contact_rows added) -> update_contacts -> while it changed,
  // then finish_contacts on the last solution and advance.
  /// Activates the nodes that were in contact at the end of the previous step (the active set a
  /// body resting on a floor keeps), so a resting contact costs no extra solve. Call after
  /// form_system. @return true if any was activated.
  bool warm_start_contacts(double h);
  /// Releases the constraints whose force f_c = κ (target − n·u^{n+1}) would pull and activates
  /// every free node whose end-of-step position xⁿ + (h/2)(uⁿ + u^{n+1}) lies inside an obstacle,
  /// with the landing constraint n·u^{n+1} = −2 φⁿ/h − n·uⁿ (see step()).
  /// @param u_next  a solution u^{n+1} (this solid's velocities at dof `offset`)
  /// @return true if the active set changed (add contact_rows and solve again)
  bool update_contacts(double h, const Eigen::VectorXd& u_next, int offset = 0);
  /// Adds the active constraints' rows at dof offset `offset` of a larger system (A must hold the
  /// diagonal blocks already): the penalty κ n nᵀ + c_t (I − n nᵀ) to the node's diagonal block
  /// and κ target n to b, c_t the friction of the contact (see step()).
  void add_contact_rows(SparseMatrix& A, Eigen::VectorXd& b, int offset = 0) const;
  /// The constraint forces of the final solution (the next step's friction starts from them).
  void finish_contacts(const Eigen::VectorXd& u_next, int offset = 0);
  /// The sum of the last step's contact forces on the solid [N] (the obstacles' push: f n per
  /// contact node), 0 without contact.
  Eigen::Vector3d contact_force() const { return contact_force_; }
  /// The smallest signed distance of a node to the obstacles at the current displacement [m]
  /// (negative: inside one; +infinity without obstacles). For a wall set back by a fluid film, the
  /// distance to the film's surface.
  double obstacle_clearance() const;
  int num_active_contacts() const { return static_cast<int>(active_.size()); }

  // ---- whole step ----
  /// One step of length h [s] (the caller's: the settings hold no step): form_system + solve + advance. With obstacles, contact is part of the implicit solve
  /// (active set): every free node whose end-of-step position would lie inside an obstacle
  /// gets the constraint n.u^{n+1} = -2 phi^n / h - n.u^n (it lands on the surface at t^{n+1}
  /// by eq. 5), imposed by a stiff penalty kappa n n^T on its diagonal block (kappa =
  /// NewmarkSettings::contact_penalty x the block's diagonal), and the system is solved again (at most 8 rounds; nodes whose
  /// constraint force would pull are released). The rest of the body thus responds to the
  /// contact within the same step. Coulomb friction is in the same solve: a contact with normal
  /// force f_c (that of the previous round, or of the previous step for a contact that goes on)
  /// gets the tangential damping c_t (I - n n^T), c_t = mu f_c / max(|v_t|, eps_v), v_t its
  /// tangential velocity in that solve: the force -c_t v_t is mu f_c against the slip when it
  /// slides and holds it (creep below eps_v = NewmarkSettings::friction_velocity) when it sticks,
  /// the lagged smoothed Coulomb law of Li et al. 2020 (IPC, sec. 5) with one Picard update per
  /// round (a round whose c_t moved by more than 1% is solved again). After eq. (5), constrained
  /// nodes lose their normal velocity (inelastic); in a coupled step the closed fluid regions'
  /// start-velocity projection (coupling/closed_regions.hpp) then gives back what that changes of
  /// a closed volume. Nodes still inside are projected (StaticObstacles::project).
  /// @throws SolidError (see above)
  const StepStats& step(double h);

  // ---- state ----
  const Eigen::VectorXd& displacement() const { return d_; }
  const Eigen::VectorXd& velocity() const { return u_; }
  Eigen::VectorXd positions() const { return model_.reference_positions() + d_; }
  double time() const { return time_; }
  int step_index() const { return step_; }
  const std::vector<char>& fixed_dofs() const { return fixed_; }
  const StepStats& last_stats() const { return stats_; }
  const NewmarkSettings& settings() const { return settings_; }
  const ElasticModel& model() const { return model_; }
  /// Energies of the current state (fills the energy fields of a StepStats).
  StepStats energies() const;

  /// The state a step changes (to retry it with a shorter step: save_state, step, restore_state).
  struct State {
    Eigen::VectorXd d, u;
    double time = 0;
    int step = 0;
    StepStats stats;
    std::vector<int> last_contact_nodes;
    std::vector<double> last_contact_forces;
  };
  State save_state() const { return {d_, u_, time_, step_, stats_, last_contact_nodes_, last_contact_forces_}; }
  void restore_state(const State& s) {
    d_ = s.d, u_ = s.u, time_ = s.time, step_ = s.step, stats_ = s.stats, last_contact_nodes_ = s.last_contact_nodes;
    last_contact_forces_ = s.last_contact_forces;
    active_.clear();
  }
  /// Checkpoints (newmark_state.cpp): save_state()'s State, the prescribed velocities, the external
  /// forces and the self-contact's touching nodes, bit for bit. The model, settings, fixed dofs,
  /// springs and obstacles are the set-up's: read into an integrator set up from the same scene.
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);

 private:
  const ElasticModel& model_;
  NewmarkSettings settings_;
  Eigen::VectorXd d_, u_, f_ext_, prescribed_;
  std::vector<char> fixed_;
  std::vector<LinearSpring> springs_;
  StaticObstacles obstacles_;
  std::unique_ptr<SurfaceContact> self_contact_;
  SpdSolver solver_;
  struct ActiveContact {
    int node;
    Eigen::Vector3d normal;
    double target;   // n.u^{n+1} [m/s]
    double kappa;    // penalty [kg/s]
    double force;    // constraint force along n [N], after the solve
    double friction = 0;  // c_t [kg/s] (see step())
  };
  std::vector<ActiveContact> active_;
  std::vector<int> last_contact_nodes_;      // nodes in contact at the end of the last step
  std::vector<double> last_contact_forces_;  // and their normal forces [N]
  Eigen::Vector3d contact_force_ = Eigen::Vector3d::Zero();  // sum of the last step's f n [N]
  /// Adds node v's landing constraint to active_ (normal and φⁿ from its position at dⁿ), with
  /// the friction of the normal force `force` [N] and the tangential velocity of u at the node.
  void activate_contact(int v, double h, const Eigen::Vector3d& normal, double force = 0);
  /// A round whose friction coefficients c_t changed by more than this fraction is solved again
  /// (the Picard iteration of the lagged friction, step()).
  static constexpr double kFrictionChange = 0.01;
  /// c_t = μ f / max(|v_t|, ε_v) of a contact (step()).
  double friction_damping(double force, const Eigen::Vector3d& normal, const Eigen::Vector3d& velocity) const;
  /// Solves A u = b with the contact active set (see step()); fills active_.
  void solve_with_contact(double h, const std::string& context);
  SparseMatrix K_tangent_, A_;
  Eigen::VectorXd K_force_, b_, u_next_;
  double time_ = 0;
  int step_ = 0;
  StepStats stats_;
};

}  // namespace tetfsi::solid
