#pragma once
/// @file mesh_motion.hpp
/// Moving the fluid vertices of a fluid-solid complex with the solids, by a stiffened Laplacian:
/// the "Jacobian-based stiffening" of Tezduyar et al. (Stein, Tezduyar & Benney 2003, "Mesh moving
/// techniques for fluid-structure interactions with large displacements", J. Appl. Mech. 70).
///
/// The displacement d of the fluid vertices minimises Σ_t s_t ∫_t |∇d|² dV with d prescribed on
/// the solid vertices (their motion) and on the boundary of the mesh (0: the box stays), where d is
/// P1 on each tet and the stiffness of tet t is
///
///     s_t = (V_max / V_t)^χ,
///
/// so small tets (those next to the solids, in a graded mesh) are stiffer and move almost rigidly
/// with the solid, and the distortion goes into the large tets farther away. χ = 0 is the plain
/// P1 harmonic extension; Stein et al. use χ = 1. The system, Σ_t s_t V_t G_tᵀ G_t (G_t the P1
/// gradient of tet t), is symmetric positive definite once the Dirichlet vertices are eliminated;
/// it is solved for the three components by conjugate gradients (diagonal, or a given SPD
/// preconditioner such as an algebraic multigrid V-cycle) or by a Cholesky factorization.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <Eigen/IterativeLinearSolvers>
#include <functional>
#include <memory>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

namespace tetfsi::mesh {

struct MeshMotionOptions {
  double stiffening_exponent = 1.0;  ///< χ of s_t = (V_max / V_t)^χ
  /// MeshMotion only: factorize the operator (CHOLMOD supernodal Cholesky, at the second call on a
  /// mesh; the three displacement components are solved as one block) instead of CG at every call.
  /// Pays when the same mesh is moved for many steps (the coupled step between remeshes): the
  /// motion at 197k tets takes about 0.03 s per step (the whole mesh update took 0.27 s with CG).
  bool factorize = false;
  /// CG relative residual. The motion only has to keep tets valid, not be accurate: 1e-8 takes
  /// about half the iterations of 1e-10 (the remesher used 1e-6 for its plain extension).
  double tolerance = 1e-8;
  /// MeshMotion's preconditioned CG only: it also stops once the residual is this fraction of the
  /// residual of its initial guess (the extrapolated motion), whichever comes first. The guess is
  /// already close, so the error left is this fraction of one step's change of the motion (the
  /// extrapolation then amplifies the previous step's error at most threefold, so the errors do
  /// not build up): 1e-3 of a step's displacement of the vertices next to a solid is far below
  /// their edge length, and takes 5 BoomerAMG-CG iterations per component at 409k fluid tets
  /// where 1e-8 of the whole motion took 12-15. 0: the tolerance alone.
  double step_reduction = 1e-3;
  /// z ≈ K⁻¹ r for a symmetric positive definite K, applied to one component at a time.
  using Preconditioner = std::function<void(const Eigen::VectorXd& r, Eigen::VectorXd& z)>;
  /// MeshMotion only: builds the preconditioner of CG for the operator K, at the first call that
  /// solves by CG (every call without `factorize`, the first one with it). The coupled step
  /// passes one BoomerAMG V-cycle (coupling/mesh_update.cpp): set up once per mesh, a step then
  /// costs a few V-cycles per component, with no factorization (seconds at a million tets) and no
  /// factor in memory (the largest item of the step's memory). Empty: the diagonal of K.
  std::function<Preconditioner(const Eigen::SparseMatrix<double>& K)> make_preconditioner;
};

/// New positions of every vertex of `mesh`: solid vertices (those of a tet with a label other than
/// kFluidSubdomain) at `solid_positions`, vertices on the mesh boundary (faces of one tet only) that
/// are not solid vertices fixed, every other vertex moved by the stiffened Laplacian above.
/// @param mesh             the complex at its current positions (positively oriented fluid tets)
/// @param solid_positions  one position per vertex; read only for solid vertices [m]
/// @throws MeshError if the sizes do not match or CG does not converge
std::vector<Eigen::Vector3d> move_with_solids(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                                              const MeshMotionOptions& options = {});

/// The same motion measured from a fixed reference mesh, for many steps on one mesh: the
/// stiffened Laplacian is assembled once at the reference positions, and each call solves it for
/// the total displacement of the solid vertices since the reference (CG warm-started from the
/// previous call's solution). Cheaper per step than move_with_solids (no assembly, few CG
/// iterations), and the same up to the change of geometry since the reference; build a new one
/// after the mesh is remeshed.
class MeshMotion {
 public:
  /// @param reference  the mesh whose connectivity and positions define the operator
  /// @throws MeshError if a fluid tet of the reference is flat or inverted
  MeshMotion(const TetMesh& reference, const MeshMotionOptions& options = {});
  ~MeshMotion();

  /// Positions of every vertex of the reference mesh with the solid vertices at
  /// `solid_positions` (one per vertex, read for solid vertices) [m].
  /// @throws MeshError on a size mismatch or if CG does not converge
  std::vector<Eigen::Vector3d> positions(const std::vector<Eigen::Vector3d>& solid_positions);

  int num_vertices() const { return static_cast<int>(reference_.size()); }
  /// CG iterations of the last positions() over the three components (preconditioned CG only).
  int last_iterations() const { return last_iterations_; }
  /// The reference positions the operator was assembled at [m].
  const std::vector<Eigen::Vector3d>& reference_positions() const { return reference_; }

  /// Checkpoints: the two previous solutions (CG's initial guess extrapolates them) and the call
  /// count that decides the factorization. Restore into a MeshMotion built from the same reference mesh and options; it
  /// factorizes again if the saved one had, so the next positions() is bit for bit the saved one's.
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);

 private:
  struct Solver;
  /// last_ = K_ff⁻¹ rhs column by column, by CG with precondition_ from the extrapolated guess.
  void solve_preconditioned(const Eigen::MatrixXd& rhs);
  std::vector<Eigen::Vector3d> reference_;
  std::vector<int> kind_, unknown_;
  Eigen::SparseMatrix<double> K_ff_, K_fp_;  // free-free and free-prescribed blocks
  std::vector<int> prescribed_;               // vertex of each K_fp_ column
  std::unique_ptr<Solver> solver_;
  Eigen::MatrixXd last_;                      // previous solution (m x 3)
  Eigen::MatrixXd before_last_;               // the one before it (m x 3, empty until two calls)
  std::function<MeshMotionOptions::Preconditioner(const Eigen::SparseMatrix<double>&)> make_preconditioner_;
  MeshMotionOptions::Preconditioner precondition_;  // made at the first preconditioned solve
  double tolerance_ = 1e-8;
  double step_reduction_ = 1e-3;
  int max_iterations_ = 1000;
  int last_iterations_ = 0;
  bool factorize_ = false;
  int calls_ = 0;
};

}  // namespace tetfsi::mesh
