// Forward and backward solves with a supernodal Cholesky factor (supernodal_solve.hpp).
#include "coupling/solvers/supernodal_solve.hpp"

#include <Eigen/Core>
#include <algorithm>

namespace tetfsi::coupling::detail {

namespace {

template <class Scalar>
using Block = Eigen::Map<const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>, 0, Eigen::OuterStride<>>;

/// Supernode k's dense block (rows × columns, leading dimension rows).
template <class Scalar>
Block<Scalar> supernode_block(const SupernodalFactorView<Scalar>& L, int k, int rows, int columns) {
  return Block<Scalar>(L.values + L.first_value[k], rows, columns, Eigen::OuterStride<>(rows));
}

}  // namespace

template <class Scalar>
void supernodal_solve(const SupernodalFactorView<Scalar>& L, const double* b, double* x,
                      SupernodalWorkspace<Scalar>& work) {
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  const int n = L.n;
  work.y.resize(n);
  int widest_below = 0;
  for (int k = 0; k < L.num_supernodes; ++k)
    widest_below = std::max(widest_below, (L.first_row[k + 1] - L.first_row[k]) - (L.first_column[k + 1] - L.first_column[k]));
  work.gathered.resize(widest_below);
  Scalar* y = work.y.data();
  for (int i = 0; i < n; ++i) y[i] = static_cast<Scalar>(b[L.permutation[i]]);  // y = Q b

  // L y' = y, supernode by supernode: y_k ← L_kk⁻¹ y_k, then y_r ← y_r − L_rk y_k.
  for (int k = 0; k < L.num_supernodes; ++k) {
    const int columns = L.first_column[k + 1] - L.first_column[k], rows = L.first_row[k + 1] - L.first_row[k];
    const int below = rows - columns;
    const Block<Scalar> Lk = supernode_block(L, k, rows, columns);
    Eigen::Map<Vector> y_k(y + L.first_column[k], columns);
    Lk.topRows(columns).template triangularView<Eigen::Lower>().solveInPlace(y_k);
    if (below == 0) continue;
    Eigen::Map<Vector> update(work.gathered.data(), below);
    update.noalias() = Lk.bottomRows(below) * y_k;
    const int* row = L.row_index + L.first_row[k] + columns;
    for (int i = 0; i < below; ++i) y[row[i]] -= update[i];
  }
  // Lᵀ y'' = y', in reverse: y_k ← y_k − L_rkᵀ y_r, then y_k ← L_kk⁻ᵀ y_k.
  for (int k = L.num_supernodes - 1; k >= 0; --k) {
    const int columns = L.first_column[k + 1] - L.first_column[k], rows = L.first_row[k + 1] - L.first_row[k];
    const int below = rows - columns;
    const Block<Scalar> Lk = supernode_block(L, k, rows, columns);
    Eigen::Map<Vector> y_k(y + L.first_column[k], columns);
    if (below > 0) {
      Eigen::Map<Vector> y_r(work.gathered.data(), below);
      const int* row = L.row_index + L.first_row[k] + columns;
      for (int i = 0; i < below; ++i) y_r[i] = y[row[i]];
      y_k.noalias() -= Lk.bottomRows(below).transpose() * y_r;
    }
    Lk.topRows(columns).transpose().template triangularView<Eigen::Upper>().solveInPlace(y_k);
  }
  for (int i = 0; i < n; ++i) x[L.permutation[i]] = static_cast<double>(y[i]);  // x = Qᵀ y
}

template void supernodal_solve<double>(const SupernodalFactorView<double>&, const double*, double*,
                                       SupernodalWorkspace<double>&);
template void supernodal_solve<float>(const SupernodalFactorView<float>&, const double*, double*,
                                      SupernodalWorkspace<float>&);

}  // namespace tetfsi::coupling::detail
