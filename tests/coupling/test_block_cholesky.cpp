// BlockCholesky (coupling/solvers/block_cholesky.hpp): one factor per connected component of an
// SPD matrix, its solve against a dense one, and its verdict on a block that is not positive definite.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
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

/// A 3D vector Laplacian plus mass on two n x n x n grids of nodes with 3 dofs each, the second
/// grid's dofs interleaved with the first's (two bodies), and a diagonal spread by `spread`
/// (entry i of body b scaled by spread^(i / size)): supernodes many columns wide, as a tet solid's.
SparseMatrix two_grids(int n, double spread) {
  const int nodes = n * n * n, size = 3 * nodes;
  std::vector<Eigen::Triplet<double>> t;
  auto dof = [&](int body, int node, int c) { return 2 * (3 * node + c) + body; };
  for (int body = 0; body < 2; ++body)
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const int node = x + n * (y + n * z);
          const int nb[3] = {x + 1 < n ? node + 1 : -1, y + 1 < n ? node + n : -1, z + 1 < n ? node + n * n : -1};
          for (int c = 0; c < 3; ++c) {
            const int i = dof(body, node, c);
            t.emplace_back(i, i, (6.0 + 0.5) * std::pow(spread, double(3 * node + c) / size));
            for (int q : nb)
              if (q >= 0) {
                t.emplace_back(i, dof(body, q, c), -1.0);
                t.emplace_back(dof(body, q, c), i, -1.0);
              }
            if (c > 0) {  // couple the components as an elastic stiffness does
              t.emplace_back(i, dof(body, node, 0), 0.3);
              t.emplace_back(dof(body, node, 0), i, 0.3);
            }
          }
        }
  SparseMatrix A(2 * size, 2 * size);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(BlockCholesky, SolvesInDoubleAndInSinglePrecisionThenFactorizesInDoubleAgain) {
  // The hand-written supernodal solves (supernodal_solve.hpp) against a dense solve: to round-off
  // with the double factor, to float's rounding times the condition with the single one (and
  // visibly not to round-off: the conversion happened), and to round-off after the next factorization.
  const SparseMatrix A = two_grids(7, 1.0);
  BlockCholesky cholesky;
  cholesky.analyze_pattern(A);
  ASSERT_EQ(cholesky.num_blocks(), 2);
  ASSERT_TRUE(cholesky.factorize(A));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1.0, 3.0);
  const Eigen::VectorXd dense = Eigen::MatrixXd(A).llt().solve(b);
  Eigen::VectorXd x;
  cholesky.solve(b, x);
  EXPECT_LT((x - dense).norm(), 1e-12 * dense.norm());
  ASSERT_TRUE(cholesky.to_single_precision());
  cholesky.solve(b, x);
  const double single_error = (x - dense).norm() / dense.norm();
  EXPECT_LT(single_error, 1e-5);
  EXPECT_GT(single_error, 1e-12);
  ASSERT_TRUE(cholesky.factorize(2.0 * A));
  cholesky.solve(b, x);
  EXPECT_LT((x - 0.5 * dense).norm(), 1e-12 * dense.norm());
}

TEST(BlockCholesky, AnIllConditionedBlockStaysInDoublePrecision) {
  // A diagonal spread over 1e10 makes CHOLMOD's reciprocal condition estimate (min Lᵢᵢ / max Lᵢᵢ)²
  // about 1e-10, below kSingleAboveReciprocalCondition: the factor is kept in double, and the
  // solve stays at round-off.
  const SparseMatrix A = two_grids(5, 1e10);
  BlockCholesky cholesky;
  cholesky.analyze_pattern(A);
  ASSERT_TRUE(cholesky.factorize(A));
  EXPECT_FALSE(cholesky.to_single_precision());
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(A.rows());
  const Eigen::VectorXd dense = Eigen::MatrixXd(A).llt().solve(b);
  Eigen::VectorXd x;
  cholesky.solve(b, x);
  EXPECT_LT((x - dense).norm(), 1e-10 * dense.norm());
}

}  // namespace
}  // namespace tetfsi::coupling::detail
