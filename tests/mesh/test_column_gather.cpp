// mesh::gather_columns (mesh/column_gather.hpp): the column-by-column assembly of element blocks
// against Eigen's triplet sum, bit for bit, on a restricted row and column set.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <random>
#include <vector>

#include "mesh/column_gather.hpp"

namespace tetfsi::mesh {
namespace {

TEST(ColumnGather, EqualsTheTripletSumInElementOrderBitForBit) {
  // 600 random "tets" on 200 vertices with random 4x4 blocks; rows: every vertex but the multiples
  // of 7, columns: the odd vertices. The triplets are pushed element by element, so
  // setFromTriplets sums each entry's terms in element order, the order the gather emits them in.
  const int num_vertices = 200, num_elements = 600;
  std::mt19937 random(7);
  std::uniform_int_distribution<int> vertex(0, num_vertices - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<std::array<int, 4>> element(num_elements);
  std::vector<Eigen::Matrix4d> block(num_elements);
  for (int e = 0; e < num_elements; ++e) {
    for (int a = 0; a < 4; ++a) {
      int v = vertex(random);
      for (int b = 0; b < a; ++b) v = v == element[e][b] ? (v + 1) % num_vertices : v;
      element[e][a] = v;
    }
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) block[e](a, b) = value(random);
  }
  std::vector<int> row_of(num_vertices, -1), column_vertex, column_of(num_vertices, -1);
  int num_rows = 0;
  for (int v = 0; v < num_vertices; ++v)
    if (v % 7 != 0) row_of[v] = num_rows++;
  for (int v = 1; v < num_vertices; v += 2) {
    column_of[v] = static_cast<int>(column_vertex.size());
    column_vertex.push_back(v);
  }
  // Elements around each vertex, ascending.
  std::vector<std::vector<std::pair<int, int>>> around(num_vertices);
  for (int e = 0; e < num_elements; ++e)
    for (int b = 0; b < 4; ++b) around[element[e][b]].emplace_back(e, b);

  // The gather of the first `used` elements (the others left out), reusing `earlier` if given.
  auto gather = [&](int used, Eigen::SparseMatrix<double>* earlier) {
    return gather_columns(
        num_rows, static_cast<int>(column_vertex.size()),
        [&](int c, const auto& emit) {
          for (const auto& [e, b] : around[column_vertex[c]])
            for (int a = 0; a < 4; ++a)
              if (e < used && row_of[element[e][a]] >= 0)
                emit(row_of[element[e][a]], [&, e = e, b = b] { return block[e](a, b); });
        },
        0.5, earlier);
  };
  const Eigen::SparseMatrix<double> gathered = gather(num_elements, nullptr);
  std::vector<Eigen::Triplet<double>> triplets;
  for (int e = 0; e < num_elements; ++e)
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a)
        if (row_of[element[e][a]] >= 0 && column_of[element[e][b]] >= 0)
          triplets.emplace_back(row_of[element[e][a]], column_of[element[e][b]], block[e](a, b));
  Eigen::SparseMatrix<double> summed(num_rows, static_cast<int>(column_vertex.size()));
  summed.setFromTriplets(triplets.begin(), triplets.end());
  summed *= 0.5;
  ASSERT_EQ(gathered.nonZeros(), summed.nonZeros());
  const Eigen::MatrixXd difference = Eigen::MatrixXd(gathered) - Eigen::MatrixXd(summed);
  EXPECT_EQ(difference.cwiseAbs().maxCoeff(), 0.0);

  // New values on the same elements (a moved mesh): summed into the earlier pattern, which the
  // result takes over, bit for bit the full gather's.
  for (auto& k : block) k *= -1.5;
  Eigen::SparseMatrix<double> earlier = gathered;
  const double* earlier_values = earlier.valuePtr();
  const Eigen::SparseMatrix<double> reused = gather(num_elements, &earlier);
  EXPECT_EQ(reused.valuePtr(), earlier_values) << "the earlier matrix's storage is taken over";
  const Eigen::SparseMatrix<double> fresh = gather(num_elements, nullptr);
  ASSERT_EQ(reused.nonZeros(), fresh.nonZeros());
  EXPECT_EQ((Eigen::MatrixXd(reused) - Eigen::MatrixXd(fresh)).cwiseAbs().maxCoeff(), 0.0);
  // Fewer elements: some earlier entries get no term, so the pattern differs and the full gather
  // runs (no explicit zeros left behind).
  Eigen::SparseMatrix<double> stale = gathered;
  const Eigen::SparseMatrix<double> fewer = gather(num_elements / 2, &stale);
  const Eigen::SparseMatrix<double> fewer_fresh = gather(num_elements / 2, nullptr);
  EXPECT_LT(fewer.nonZeros(), gathered.nonZeros());
  ASSERT_EQ(fewer.nonZeros(), fewer_fresh.nonZeros());
  EXPECT_EQ((Eigen::MatrixXd(fewer) - Eigen::MatrixXd(fewer_fresh)).cwiseAbs().maxCoeff(), 0.0);
  // More elements than the earlier pattern holds: a term off the pattern, the full gather again.
  Eigen::SparseMatrix<double> small = fewer_fresh;
  const Eigen::SparseMatrix<double> more = gather(num_elements, &small);
  ASSERT_EQ(more.nonZeros(), fresh.nonZeros());
  EXPECT_EQ((Eigen::MatrixXd(more) - Eigen::MatrixXd(fresh)).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace tetfsi::mesh
