// Restarted right-preconditioned GMRES (see gmres.hpp).
#include "coupling/solvers/gmres.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace tetfsi::coupling::detail {

GmresResult right_preconditioned_gmres(const LinearMap& apply, const LinearMap& precondition, const Eigen::VectorXd& f,
                                       Eigen::VectorXd& x, double target, int max_iterations, int restart) {
  GmresResult result;
  const Eigen::Index size = f.size();
  if (x.size() != size) x = Eigen::VectorXd::Zero(size);
  // Arnoldi basis of K M⁻¹, grown one vector per Krylov step (a solve that converges in 25 steps
  // touches 26 vectors, not restart + 1).
  std::vector<Eigen::VectorXd> V;
  V.reserve(restart + 1);
  Eigen::MatrixXd Hess = Eigen::MatrixXd::Zero(restart + 1, restart);
  Eigen::VectorXd cs(restart), sn(restart), g(restart + 1), w(size), z(size), Kx(size), x_before;
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
      precondition(V[k], z);
      apply(z, w);
      const double w_norm = w.norm();
      // Modified Gram-Schmidt (Alg. 6.2).
      for (int i = 0; i <= k; ++i) {
        Hess(i, k) = V[i].dot(w);
        w -= Hess(i, k) * V[i];
      }
      Hess(k + 1, k) = w.norm();
      // Breakdown: K M⁻¹ V_k lies in span(V_k) up to rounding, so the least-squares iterate is the
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
    // x += M⁻¹ V_k y with Hess_k y = g_k (upper triangular after the rotations).
    const Eigen::VectorXd y =
        Hess.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
    Eigen::VectorXd Vy = y[0] * V[0];
    for (int i = 1; i < k; ++i) Vy += y[i] * V[i];
    precondition(Vy, z);
    x += z;
  }
}

}  // namespace tetfsi::coupling::detail
