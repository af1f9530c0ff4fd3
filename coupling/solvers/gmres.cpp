// Restarted flexible right-preconditioned GMRES (see gmres.hpp).
#include "coupling/solvers/gmres.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace tetfsi::coupling::detail {

namespace {

/// Modified Gram-Schmidt (Saad, Alg. 6.2) of w against V[0..k]: h_i = V_i · w, w ← w − h_i V_i,
/// i = 0 … k, in parallel over fixed blocks of the vectors. Each subtraction is fused with the next
/// dot product (one pass over w per basis vector), and the blocks' partial sums are added in block
/// order, so the result is the same for any number of threads.
void orthogonalize(const std::vector<Eigen::VectorXd>& V, int k, Eigen::VectorXd& w, Eigen::MatrixXd& Hess) {
  constexpr Eigen::Index kBlock = 16384;
  const Eigen::Index size = w.size();
  const int blocks = static_cast<int>((size + kBlock - 1) / kBlock);
  std::vector<double> partial(blocks);
  auto segment = [&](int b) { return std::pair<Eigen::Index, Eigen::Index>(b * kBlock, std::min(kBlock, size - b * kBlock)); };
  auto ordered_sum = [&] {
    double sum = 0;
    for (double p : partial) sum += p;
    return sum;
  };
  tbb::parallel_for(0, blocks, [&](int b) {
    const auto [first, n] = segment(b);
    partial[b] = V[0].segment(first, n).dot(w.segment(first, n));
  });
  for (int i = 0; i <= k; ++i) {
    const double h = Hess(i, k) = ordered_sum();
    tbb::parallel_for(0, blocks, [&](int b) {
      const auto [first, n] = segment(b);
      w.segment(first, n) -= h * V[i].segment(first, n);
      if (i < k) partial[b] = V[i + 1].segment(first, n).dot(w.segment(first, n));
    });
  }
}

}  // namespace

GmresResult right_preconditioned_gmres(const LinearMap& apply, const LinearMap& precondition, const Eigen::VectorXd& f,
                                       Eigen::VectorXd& x, double target, int max_iterations, int restart) {
  GmresResult result;
  const Eigen::Index size = f.size();
  if (x.size() != size) x = Eigen::VectorXd::Zero(size);
  // Arnoldi basis of K M⁻¹ and the preconditioned vectors, grown one vector each per Krylov step
  // (a solve that converges in 25 steps touches 26 + 25 vectors, not 2 restart + 1).
  std::vector<Eigen::VectorXd> V, Z;  // Z[k] = M⁻¹ V[k], kept (flexible GMRES)
  V.reserve(restart + 1);
  Z.reserve(restart);
  Eigen::MatrixXd Hess = Eigen::MatrixXd::Zero(restart + 1, restart);
  Eigen::VectorXd cs(restart), sn(restart), g(restart + 1), w(size), Kx(size), x_before;
  double beta_before = std::numeric_limits<double>::infinity();
  while (true) {
    apply(x, Kx);
    Eigen::VectorXd r = f - Kx;
    const double beta = r.norm();
    if (!(beta < beta_before)) {
      // The last cycle did not reduce the true residual (stagnation at the attainable accuracy,
      // or a breakdown that rounding turned into a bad basis): keep the iterate before it.
      if (x_before.size() == size) x = x_before;
      result.residual = beta_before;
      result.converged = beta_before <= target;
      return result;
    }
    result.residual = beta;
    result.converged = beta <= target;
    if (result.converged || result.iterations >= max_iterations) return result;
    x_before = x;
    beta_before = beta;
    if (V.empty()) V.emplace_back(size);
    V[0] = r / beta;
    g.setZero();
    g(0) = beta;
    int k = 0;  // Krylov steps in this cycle
    for (; k < restart && result.iterations < max_iterations; ++k) {
      ++result.iterations;
      if (static_cast<int>(Z.size()) == k) Z.emplace_back(size);
      precondition(V[k], Z[k]);
      apply(Z[k], w);
      const double w_norm = w.norm();
      orthogonalize(V, k, w, Hess);
      Hess(k + 1, k) = w.norm();
      // Breakdown: K Z_k lies in span(V_k) up to rounding, so the least-squares iterate is the
      // solution in this space; normalizing the rounding noise would give a non-orthogonal basis.
      const bool breakdown = !(Hess(k + 1, k) > 1e-14 * w_norm);
      if (breakdown) Hess(k + 1, k) = 0;
      else {
        if (static_cast<int>(V.size()) == k + 1) V.emplace_back(size);
        V[k + 1] = w / Hess(k + 1, k);
      }
      // Apply the previous rotations to the new column, then the one that zeroes Hess(k+1, k).
      for (int i = 0; i < k; ++i) {
        const double t = cs(i) * Hess(i, k) + sn(i) * Hess(i + 1, k);
        Hess(i + 1, k) = -sn(i) * Hess(i, k) + cs(i) * Hess(i + 1, k);
        Hess(i, k) = t;
      }
      const double d = std::hypot(Hess(k, k), Hess(k + 1, k));
      cs(k) = d > 0 ? Hess(k, k) / d : 1.0;
      sn(k) = d > 0 ? Hess(k + 1, k) / d : 0.0;
      Hess(k, k) = d;
      Hess(k + 1, k) = 0;
      g(k + 1) = -sn(k) * g(k);
      g(k) *= cs(k);
      if (Hess(k, k) == 0) break;  // singular least-squares problem: column k is not used
      // |g(k+1)| is the residual norm of the least-squares iterate (exact arithmetic).
      if (std::abs(g(k + 1)) <= target || breakdown) {
        ++k;
        break;
      }
    }
    if (k == 0) return result;  // nothing to add (singular at the first step)
    // x += Z_k y with Hess_k y = g_k (upper triangular after the rotations).
    const Eigen::VectorXd y =
        Hess.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
    for (int i = 0; i < k; ++i) x += y[i] * Z[i];
  }
}

}  // namespace tetfsi::coupling::detail
