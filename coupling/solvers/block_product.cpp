// Parallel block products of eq. (7) (see block_product.hpp).
#include "coupling/solvers/block_product.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace tetfsi::coupling::detail {
namespace {

/// Column j of M dotted with x, summed in storage order.
double column_dot(const SparseMatrix& M, int j, const Eigen::Ref<const Eigen::VectorXd>& x) {
  double sum = 0;
  for (SparseMatrix::InnerIterator it(M, j); it; ++it) sum += it.value() * x[it.index()];
  return sum;
}

/// Calls f(j) for every j in [0, count), in parallel.
template <class F>
void for_each_column(int count, F&& f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, count, 1024), [&](const tbb::blocked_range<int>& range) {
    for (int j = range.begin(); j < range.end(); ++j) f(j);
  });
}

}  // namespace

BlockProducts::BlockProducts(const CoupledSystem& s) : s_(s), H_transpose_(s.H.transpose()) {}

void BlockProducts::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y, double solid_scale,
                          double fluid_scale) const {
  const int n = s_.num_solid_dofs(), m = s_.num_pressures();
  const Eigen::Ref<const Eigen::VectorXd> x_u = x.head(n), x_p = x.tail(m);  // views, no copies
  y.resize(n + m);
  // Row j of the solid block: (A xᵤ)_j = (Aᵀ xᵤ)_j = A(:, j)·xᵤ and (Hᵀ xₚ)_j = H(:, j)·xₚ.
  for_each_column(n, [&](int j) { y[j] = (column_dot(s_.A, j, x_u) - column_dot(s_.H, j, x_p)) / solid_scale; });
  // Row i of the fluid block: (H xᵤ)_i = Hᵀ(:, i)·xᵤ and (P xₚ)_i = P(:, i)·xₚ.
  for_each_column(m, [&](int i) {
    y[n + i] = (column_dot(H_transpose_, i, x_u) + column_dot(s_.P, i, x_p)) / fluid_scale;
  });
}

void BlockProducts::interface_flux(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::VectorXd& y) const {
  y.resize(s_.num_pressures());
  for_each_column(s_.num_pressures(), [&](int i) { y[i] = column_dot(H_transpose_, i, x); });
}

}  // namespace tetfsi::coupling::detail
