#pragma once
/// @file block_cholesky.hpp
/// Cholesky factorization of a sparse symmetric positive definite matrix whose graph falls apart
/// into independent pieces: A = Qᵀ diag(A₁, …, A_k) Q for the permutation Q that groups the
/// unknowns of each connected component of A's graph, so
///
///     A⁻¹ b = Qᵀ diag(A₁⁻¹, …, A_k⁻¹) Q b,
///
/// one CHOLMOD supernodal factor Lᵢ Lᵢᵀ = Aᵢ per component, factorized and solved in parallel.
/// Eq. (7)'s solid block A = M/h + C + (h/2)K′ has one component per solid body (the flagship's two
/// sheets); a supernodal triangular solve is serial and bound by reading the factor, so the bodies'
/// solves running side by side is the one parallelism they offer. Written here because CHOLMOD
/// factors a matrix as one elimination tree and has no parallel solve. The solves are
/// supernodal_solve.hpp's on CHOLMOD's factor (CHOLMOD's own serialize on OpenBLAS's lock). A
/// matrix of one component is one factor.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

namespace tetfsi::coupling::detail {

class BlockCholesky {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;

  BlockCholesky();
  ~BlockCholesky();

  /// Finds A's connected components and analyses each block (fill-reducing ordering and symbolic
  /// factor, CHOLMOD's choice). A: square, symmetric, compressed, both triangles stored.
  void analyze_pattern(const SparseMatrix& A);
  /// Numeric factorization of every block of A (A's pattern must be the analysed one).
  /// @return false if some block is not positive definite (the factor is then unusable)
  bool factorize(const SparseMatrix& A);
  /// x = A⁻¹ b with the last factorization. One call at a time (each block has one set of work
  /// vectors).
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;

  /// Keeps each block's factor in single precision only, its double values freed (half the memory,
  /// and solves that read half the bytes), for a factor used as a preconditioner: solve() then
  /// gives A⁻¹ b to about 6e-8 times A's condition number, relative. A block whose reciprocal
  /// condition estimate (CHOLMOD's (min Lᵢᵢ / max Lᵢᵢ)², which is at least 1/cond(A): a gate, not a
  /// bound on the condition) is below kSingleAboveReciprocalCondition stays in double. The next
  /// factorize() is in double again (CHOLMOD allocates the double values anew).
  /// @return true if every block is now in single precision
  bool to_single_precision();
  static constexpr double kSingleAboveReciprocalCondition = 1e-6;

  /// Number of blocks (connected components) of the analysed pattern.
  int num_blocks() const { return static_cast<int>(blocks_.size()); }

 private:
  struct Block;
  /// The block of A on `index` (sorted; a union of components, so nothing outside is dropped).
  static SparseMatrix sub_matrix(const SparseMatrix& A, const std::vector<int>& index, const std::vector<int>& local);
  std::vector<std::unique_ptr<Block>> blocks_;
  std::vector<int> local_;  // position of each unknown within its block
  bool factorized_ = false;  // the last factorize() succeeded
};

}  // namespace tetfsi::coupling::detail
