#pragma once
/// @file surface_contact.hpp
/// Node-to-surface contact between deformable tet solids, and of a solid with itself, inside an
/// implicit step whose unknowns are the end-of-step velocities u^{n+1} of all solids (one vector,
/// solid s at its dof offset, 3 dofs per node).
///
/// A pair (a, f) is a surface node a and the surface triangle f = (i, j, k) nearest to it at the
/// start of the step, xⁿ, of another solid (or of the same solid away from a). With y = Σ w_m x_m
/// the closest point of f (barycentric weights w) and n the unit normal from y towards x_a (f's
/// outward normal where y is inside f), the gap is
///     φⁿ = n · (x_a − y) − δ,
/// δ being the film kept between the surfaces (in a coupled scene the fluid between two solids
/// must keep tets of some thickness: coupling.contact_gap). The relative normal velocity is linear
/// in u, g(u) = n · (u_a − Σ w_m u_m) = Gᵀ u. Both Newmark schemes move the nodes by
/// (h/2)(uⁿ + u^{n+1}) (eq. 5 of Chentanez et al. 2006), so the end-of-step gap is
/// φⁿ + (h/2)(g(uⁿ) + g(u^{n+1})), and a pair whose predicted gap is negative gets the landing
/// constraint
///     g(u^{n+1}) = −2 max(φⁿ, 0)/h − g(uⁿ),
/// the obstacle contact of NewmarkIntegrator (solid/integrator/newmark.hpp) with the obstacle
/// replaced by the moving triangle. It is imposed by a penalty, κ G Gᵀ added to A and κ·target·G to
/// b, κ = penalty × m_a/h (node a's inertia); pairs whose constraint force
/// f = κ (target − Gᵀ u^{n+1}) would pull are released. The force acts on a as f n and on the
/// triangle's nodes as −w_m f n: a pair conserves linear momentum. Dofs with prescribed velocity
/// (fixed or driven nodes) keep their rows; their columns of κ G Gᵀ move to b.
///
/// Coulomb friction (coefficient μ), inside the same solve: a pair with normal force f (that of
/// the previous round, or of the previous step for a pair that goes on) gets the tangential
/// damping c_t T_Gᵀ T_G, T_G u = (I − n nᵀ)(u_a − Σ w_m u_m) its relative tangential velocity v_t
/// and c_t = μ f / max(|v_t|, ε_v) from the last solve's v_t: the force −c_t v_t on a (and
/// +w_m c_t v_t on the triangle's nodes) is μ f against a slip and holds a sticking pair (creep
/// below ε_v), the lagged smoothed Coulomb law of Li et al. (2020, IPC, sec. 5) with one Picard
/// update per round (a round whose c_t moved by more than 1% is solved again, so at convergence
/// a sliding pair's friction is μ f to 1%). It conserves linear momentum as the normal force does, and, being part of
/// the solve, it acts on the fluid in the same step.
///
/// Self-contact: triangles incident to a are skipped, and so are triangles within 2δ (or half a
/// surface edge) of a in the reference configuration (parts that close at rest), triangles that a
/// lies behind at rest (the far side of a thin wall, seen through the solid) and triangles whose
/// normal does not face a's own surface normal (n_f · n_a > −1/2: neighbours on a smooth surface). What is left are
/// folds of the surface meeting from opposite sides, a bunny's ear against its head.
///
/// Search: the triangles' bounding boxes, grown by the distance a node can close in the step, in
/// a uniform hash grid whose cell is the mean surface edge length. Written here because CGAL's
/// AABB tree is kept inside mesh/ (each CGAL unit costs a minute and 3.6 GB to compile) and the
/// query is a few lines once the grid exists.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

namespace tetfsi::solid {

struct SurfaceContactSettings {
  double gap = 0;            ///< δ: film kept between the surfaces [m], >= 0
  /// κ as a multiple of the contact node's inertia m_a/h (as NewmarkIntegrator's obstacle
  /// contact): the constraint holds to about 1/κ of the node's change of momentum. 1e5, not the
  /// obstacles' 1e7: with 1e7 of A's diagonal the pair rows (which couple two solids' nodes) left
  /// the coupled fast path (schur_cg) stalled at a fluid residual of 1.0-1.2e-8 against its 1e-8
  /// tolerance when two balls met in data/scenes/balls_collide.json.
  double penalty = 1e5;
  double friction = 0;       ///< Coulomb μ >= 0
  double friction_velocity = 1e-3;  ///< ε_v [m/s]: below it a pair sticks (see the file comment)
  bool between_solids = true;  ///< pairs of different solids
};

class SurfaceContact {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;
  /// @throws std::invalid_argument on a negative gap, penalty <= 0 or negative friction
  explicit SurfaceContact(SurfaceContactSettings settings);

  /// Adds a solid: its tets (local node ids), reference positions X (3 per node) and lumped
  /// masses [kg] (1 per node); its nodes are the dofs dof_offset ... dof_offset + 3n − 1 of the
  /// system. The boundary triangles of the tets are its surface, oriented outward. With
  /// self_contact its surface also meets itself (see the file comment).
  void add_solid(const std::vector<std::array<int, 4>>& tets, const Eigen::VectorXd& X, const Eigen::VectorXd& masses,
                 int dof_offset, bool self_contact = false);
  /// True if some pair can form (two solids with between_solids, or a solid with self_contact).
  bool enabled() const;

  /// Finds the candidate pairs of a step of length h [s] from the positions x = X + dⁿ and
  /// velocities uⁿ of all solids (system dof order); `prescribed` flags the dofs whose velocity is
  /// prescribed (nodes with any such dof are not contact nodes, but their triangles are obstacles).
  void begin_step(double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u, const std::vector<char>& prescribed);
  /// Activates the pairs that touched at the end of the previous step and still touch.
  /// @return true if any was activated.
  bool warm_start();
  /// Releases pulling pairs and activates the candidates whose predicted end-of-step gap under
  /// u_next is negative. @return true if the active set changed.
  bool update(const Eigen::VectorXd& u_next);
  /// A += κ G Gᵀ + c_t T_Gᵀ T_G and b += κ target G over the active pairs (A: the matrix without
  /// contact rows, b its right-hand side; prescribed dofs as in the file comment).
  void add_rows(SparseMatrix& A, Eigen::VectorXd& b) const;
  /// Constraint forces of the final solution u_next (the next step's friction starts from them).
  void finish(const Eigen::VectorXd& u_next);
  /// The sum over the last step's pairs of the force f n that solid `solid` receives [N] (as the
  /// contact node's solid, f n; as the triangle's, −f n).
  Eigen::Vector3d contact_force(int solid) const;
  int num_active() const { return static_cast<int>(active_.size()); }
  /// Nodes in contact at the end of the last step (system node ids), for a retried step.
  const std::vector<int>& touching_nodes() const { return touching_; }
  /// Their normal forces [N], one per touching node.
  const std::vector<double>& touching_forces() const { return touching_force_; }
  void set_touching_nodes(std::vector<int> nodes, std::vector<double> forces) {
    touching_ = std::move(nodes);
    touching_force_ = std::move(forces);
    touching_force_.resize(touching_.size(), 0.0);
  }

 private:
  struct Triangle {
    std::array<int, 3> node;  // system node ids (dof / 3)
    int solid;
  };
  struct Pair {
    int node;                   // system node id of a
    int triangle;               // index into triangles_
    Eigen::Vector3d weight;     // barycentric w of y
    Eigen::Vector3d normal;     // n
    double gap;                 // φⁿ [m]
    double relative_velocity;   // g(uⁿ) [m/s]
    double target = 0;          // g(u^{n+1}) [m/s]
    double kappa = 0;           // [kg/s]
    double force = 0;           // f [N]
    double friction = 0;        // c_t [kg/s]
  };
  /// κ·G's four (node, coefficient) entries of a pair.
  std::array<std::pair<int, double>, 4> entries(const Pair& p) const;
  double relative_velocity(const Pair& p, const Eigen::VectorXd& u) const;
  /// c_t = μ f / max(|v_t|, ε_v) of pair p with normal force f under velocities u.
  double friction_damping(const Pair& p, double force, const Eigen::VectorXd& u) const;
  void activate(Pair p);
  bool node_prescribed(int v) const { return prescribed_[3 * v] || prescribed_[3 * v + 1] || prescribed_[3 * v + 2]; }

  SurfaceContactSettings settings_;
  std::vector<Triangle> triangles_;
  std::vector<int> surface_node_, node_solid_;  // surface nodes; solid of every system node
  Eigen::VectorXd X_, mass_;                    // reference positions, masses of every system node
  std::vector<std::vector<int>> node_triangles_;  // surface triangles around each system node
  int num_solids_ = 0;
  std::vector<char> self_contact_;  // per solid
  double h_ = 0;
  std::vector<char> prescribed_;
  std::vector<Pair> candidates_, active_;
  std::vector<int> touching_;
  std::vector<double> touching_force_;
  Eigen::VectorXd u_start_;                    // uⁿ of begin_step
  std::vector<Eigen::Vector3d> solid_force_;  // per solid, the last step's contact force [N]
};

}  // namespace tetfsi::solid
