// BlockCholesky (coupling/solvers/block_cholesky.hpp): one factor per connected component of an
// SPD matrix, its solve against a dense one, and its verdict on a block that is not positive definite.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <vector>

#include "coupling/solvers/block_cholesky.hpp"

namespace tetfsi::coupling::detail {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// A 1D Laplacian-plus-mass chain on each of the given index lists (the chains interleaved in the
/// numbering, as two bodies' dofs need not be contiguous), and `isolated` unknowns with a diagonal only.
SparseMatrix chains(int n, const std::vector<std::vector<int>>& chain_of, double mass) {
  std::vector<Eigen::Triplet<double>> t;
  std::vector<char> in_chain(n, 0);
  for (const auto& chain : chain_of)
    for (std::size_t k = 0; k < chain.size(); ++k) {
      in_chain[chain[k]] = 1;
      t.emplace_back(chain[k], chain[k], 2.0 + mass);
      if (k + 1 < chain.size()) {
        t.emplace_back(chain[k], chain[k + 1], -1.0);
        t.emplace_back(chain[k + 1], chain[k], -1.0);
      }
    }
  for (int i = 0; i < n; ++i)
    if (!in_chain[i]) t.emplace_back(i, i, 3.0);
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(BlockCholesky, SolvesEachComponentAsTheWholeMatrixDoes) {
  // Two bodies of 40 unknowns on the even and odd unknowns below 80, and 4 isolated unknowns
  // (< 1/16 of 84 each: they share one block). A⁻¹ b must equal the dense solve.
  const int n = 84;
  std::vector<int> even, odd;
  for (int i = 0; i < 80; ++i) (i % 2 ? odd : even).push_back(i);
  const SparseMatrix A = chains(n, {even, odd}, 0.1);
  BlockCholesky cholesky;
  cholesky.analyze_pattern(A);
  EXPECT_EQ(cholesky.num_blocks(), 3);
  ASSERT_TRUE(cholesky.factorize(A));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  Eigen::VectorXd x;
  cholesky.solve(b, x);
  const Eigen::VectorXd dense = Eigen::MatrixXd(A).llt().solve(b);
  EXPECT_LT((x - dense).norm(), 1e-12 * dense.norm());
  // Refactorized with other values on the same pattern: the new solution.
  const SparseMatrix B = chains(n, {even, odd}, 2.0);
  ASSERT_TRUE(cholesky.factorize(B));
  cholesky.solve(b, x);
  const Eigen::VectorXd dense_b = Eigen::MatrixXd(B).llt().solve(b);
  EXPECT_LT((x - dense_b).norm(), 1e-12 * dense_b.norm());
}

TEST(BlockCholesky, OneComponentIsOneFactor) {
  std::vector<int> all(50);
  for (int i = 0; i < 50; ++i) all[i] = i;
  const SparseMatrix A = chains(50, {all}, 0.0);
  BlockCholesky cholesky;
  cholesky.analyze_pattern(A);
  EXPECT_EQ(cholesky.num_blocks(), 1);
  ASSERT_TRUE(cholesky.factorize(A));
  Eigen::VectorXd x;
  cholesky.solve(Eigen::VectorXd::Ones(50), x);
  EXPECT_LT((A * x - Eigen::VectorXd::Ones(50)).norm(), 1e-10);
}

TEST(BlockCholesky, ABlockThatIsNotPositiveDefiniteFailsTheFactorization) {
  // The second body's chain with a negative mass large enough to make it indefinite.
  std::vector<int> first, second;
  for (int i = 0; i < 40; ++i) (i < 20 ? first : second).push_back(i);
  SparseMatrix A = chains(40, {first, second}, 0.1);
  for (int i : second) A.coeffRef(i, i) = -1.0;
  BlockCholesky cholesky;
  cholesky.analyze_pattern(A);
  EXPECT_EQ(cholesky.num_blocks(), 2);
  EXPECT_FALSE(cholesky.factorize(A));
}

TEST(BlockCholesky, AFailedFactorizationIsUndoneBitForBitByFactorizingTheEarlierMatrixAgain) {
  // SchurCGSolver::refactor overwrites its one factor and, when the new A is not positive definite,
  // factorizes the earlier A again: the solves must then be those of the earlier factor, bit for bit.
  std::vector<int> first, second;
  for (int i = 0; i < 60; ++i) (i % 3 ? first : second).push_back(i);
  const SparseMatrix A = chains(60, {first, second}, 0.3);
  SparseMatrix bad = A;
  for (int i : second) bad.coeffRef(i, i) = -1.0;
  BlockCholesky cholesky;
  cholesky.analyze_pattern(A);
  ASSERT_TRUE(cholesky.factorize(A));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(60, 0.5, -3.0);
  Eigen::VectorXd before, after;
  cholesky.solve(b, before);
  ASSERT_FALSE(cholesky.factorize(bad));
  ASSERT_TRUE(cholesky.factorize(A));
  cholesky.solve(b, after);
  ASSERT_EQ(after.size(), before.size());
  for (int i = 0; i < 60; ++i) EXPECT_EQ(after[i], before[i]) << "unknown " << i;
}

}  // namespace
}  // namespace tetfsi::coupling::detail
