#pragma once
// Helpers shared by the solid validation tests.
#include <Eigen/Core>
#include <Eigen/Cholesky>
#include <utility>
#include <cmath>
#include <vector>

namespace tetfsi::solid::testing {

/// Modal coordinate q = shape^T M d (shape M-normalized).
inline double modal_coordinate(const Eigen::VectorXd& shape, const Eigen::VectorXd& node_masses,
                               const Eigen::VectorXd& d) {
  double q = 0;
  for (Eigen::Index v = 0; v < node_masses.size(); ++v)
    q += node_masses[v] * shape.segment<3>(3 * v).dot(d.segment<3>(3 * v));
  return q;
}

/// Discrete angular frequency of an undamped sampled sinusoid q_n = A cos(n w h + phi), from
/// q_{n+1} + q_{n-1} = 2 cos(w h) q_n (least squares over all samples); exact for such a
/// sequence.
inline double sampled_frequency(const std::vector<double>& q, double h) {
  double num = 0, den = 0;
  for (size_t n = 1; n + 1 < q.size(); ++n) {
    num += q[n] * (q[n + 1] + q[n - 1]);
    den += 2 * q[n] * q[n];
  }
  return std::acos(num / den) / h;
}

/// Least-squares fit of q_{n+1} = a q_n + b q_{n-1}; returns (a, b).
inline std::pair<double, double> fit_recurrence(const std::vector<double>& q) {
  Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
  Eigen::Vector2d r = Eigen::Vector2d::Zero();
  for (size_t n = 1; n + 1 < q.size(); ++n) {
    const Eigen::Vector2d x(q[n], q[n - 1]);
    N += x * x.transpose();
    r += x * q[n + 1];
  }
  const Eigen::Vector2d ab = N.ldlt().solve(r);
  return {ab[0], ab[1]};
}

/// Exact trapezoidal (Newmark 1/4, 1/2) discrete frequency: tan(w_bar h / 2) = w h / 2.
inline double trapezoidal_frequency(double omega, double h) { return 2.0 / h * std::atan(0.5 * omega * h); }

}  // namespace tetfsi::solid::testing
