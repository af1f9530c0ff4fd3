#include "mpm/membrane/quad_frame.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace tetfsi::mpm {

QuadFrame quad_frame(const std::array<Vec3, 4>& x) {
  QuadFrame f;
  const Vec3 chi = (x[1] - x[0]) + (x[2] - x[3]);  // eq. (32)
  const Vec3 psi = (x[2] - x[0]) + (x[3] - x[1]);  // eq. (33)
  const Vec3 n = chi.cross(psi);
  if (!(n.norm() > 0)) throw std::runtime_error("membrane quad is degenerate (zero normal)");
  const Vec3 e3 = n.normalized();                           // eq. (34)
  const Vec3 alpha = (chi + psi).normalized();              // eq. (35)
  const Vec3 beta = e3.cross(alpha).normalized();           // eq. (36)
  const Vec3 e1 = (alpha - beta) / std::sqrt(2.0);          // eq. (37)
  const Vec3 e2 = (alpha + beta) / std::sqrt(2.0);          // eq. (38)
  f.q.col(0) = e1;                                          // eq. (39)
  f.q.col(1) = e2;
  f.q.col(2) = e3;
  f.center = 0.25 * (x[0] + x[1] + x[2] + x[3]);
  for (int k = 0; k < 4; ++k) {
    const Vec3 l = f.q.transpose() * (x[k] - f.center);
    f.xl[k] = l[0];
    f.yl[k] = l[1];
    f.zl[k] = l[2];
  }
  const auto& X = f.xl;
  const auto& Y = f.yl;
  f.area = 0.5 * ((X[2] - X[0]) * (Y[3] - Y[1]) + (X[1] - X[3]) * (Y[2] - Y[0]));
  if (!(f.area > 0)) throw std::runtime_error("membrane quad has non-positive area (inverted or degenerate)");
  const double s = 1.0 / (2.0 * f.area);
  f.b1 = {s * (Y[1] - Y[3]), s * (Y[2] - Y[0]), s * (Y[3] - Y[1]), s * (Y[0] - Y[2])};
  f.b2 = {s * (X[3] - X[1]), s * (X[0] - X[2]), s * (X[1] - X[3]), s * (X[2] - X[0])};
  const double h[4] = {1, -1, 1, -1};
  double hx = 0, hy = 0;
  for (int k = 0; k < 4; ++k) {
    hx += h[k] * X[k];
    hy += h[k] * Y[k];
  }
  for (int k = 0; k < 4; ++k) f.gamma[k] = 0.25 * (h[k] - hx * f.b1[k] - hy * f.b2[k]);
  f.area_vector = 0.5 * (x[2] - x[0]).cross(x[3] - x[1]);
  return f;
}

}  // namespace tetfsi::mpm
