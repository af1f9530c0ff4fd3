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
/// b, κ = penalty × the mean diagonal of A at node a; pairs whose constraint force
/// f = κ (target − Gᵀ u^{n+1}) would pull are released. The force acts on a as f n and on the
/// triangle's nodes as −w_m f n: a pair conserves linear momentum. Dofs with prescribed velocity
/// (fixed or driven nodes) keep their rows; their columns of κ G Gᵀ move to b.
///
/// Coulomb friction (coefficient μ), after the solve: the pair's relative tangential velocity v_t
/// is reduced by the impulse P = min(μ f h, m_eff |v_t|), m_eff = 1 / (1/m_a + Σ w_m² / m_m),
/// applied as −P t̂ to a and +w_m P t̂ to the triangle's nodes (t̂ = v_t / |v_t|), as Bridson, Fedkiw
/// & Anderson (2002, sec. 7.2) bound the friction impulse by μ times the normal one.
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
  /// κ as a multiple of the node's mean diagonal entry of A: the constraint holds to about 1/κ
  /// relative. 1e5, not the obstacles' 1e7: with 1e7 the pair rows (which couple two solids'
  /// nodes) left the coupled fast path (schur_cg) stalled at a fluid residual of 1.0-1.2e-8
  /// against its 1e-8 tolerance when two balls met in data/scenes/balls_collide.json; with 1e5 it
  /// converged, and the balls' centres stayed within 3.9e-4 m (0.4% of their travel) of the
  /// direct solve's (umfpack, 1e7) over the 0.4 s run.
  double penalty = 1e5;
  double friction = 0;       ///< Coulomb μ >= 0
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
  /// @param A the system matrix without contact rows (for κ). @return true if any was activated.
  bool warm_start(const SparseMatrix& A);
  /// Releases pulling pairs and activates the candidates whose predicted end-of-step gap under
  /// u_next is negative. @return true if the active set changed.
  bool update(const SparseMatrix& A, const Eigen::VectorXd& u_next);
  /// A += κ G Gᵀ and b += κ target G over the active pairs (A: the matrix without contact rows,
  /// b its right-hand side; prescribed dofs as in the file comment).
  void add_rows(SparseMatrix& A, Eigen::VectorXd& b) const;
  /// Constraint forces of the final solution u_next, then Coulomb friction applied to u_next.
  void finish(Eigen::VectorXd& u_next);
  int num_active() const { return static_cast<int>(active_.size()); }
  /// Nodes in contact at the end of the last step (system node ids), for a retried step.
  const std::vector<int>& touching_nodes() const { return touching_; }
  void set_touching_nodes(std::vector<int> nodes) { touching_ = std::move(nodes); }

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
  };
  /// κ·G's four (node, coefficient) entries of a pair.
  std::array<std::pair<int, double>, 4> entries(const Pair& p) const;
  double relative_velocity(const Pair& p, const Eigen::VectorXd& u) const;
  void activate(Pair p, const SparseMatrix& A);
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
};

}  // namespace tetfsi::solid
