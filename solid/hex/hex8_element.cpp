#include "solid/hex/hex8_element.hpp"

#include <Eigen/LU>
#include <cmath>

#include "solid/hex/tl_point.hpp"

namespace tetfsi::solid::hex {

Eigen::Matrix<double, 8, 1> hex8_shape(const Eigen::Vector3d& xi) {
  Eigen::Matrix<double, 8, 1> N;
  for (int a = 0; a < 8; ++a) {
    N(a) = 0.125 * (1 + kHexCorners[a][0] * xi.x()) * (1 + kHexCorners[a][1] * xi.y()) *
           (1 + kHexCorners[a][2] * xi.z());
  }
  return N;
}

Matrix83d hex8_shape_gradient(const Eigen::Vector3d& xi) {
  Matrix83d G;
  for (int a = 0; a < 8; ++a) {
    const double p = 1 + kHexCorners[a][0] * xi.x();
    const double q = 1 + kHexCorners[a][1] * xi.y();
    const double r = 1 + kHexCorners[a][2] * xi.z();
    G(a, 0) = 0.125 * kHexCorners[a][0] * q * r;
    G(a, 1) = 0.125 * kHexCorners[a][1] * p * r;
    G(a, 2) = 0.125 * kHexCorners[a][2] * p * q;
  }
  return G;
}

const std::array<Eigen::Vector3d, 8>& hex8_gauss_points() {
  static const std::array<Eigen::Vector3d, 8> points = [] {
    std::array<Eigen::Vector3d, 8> p;
    const double g = 1.0 / std::sqrt(3.0);
    for (int a = 0; a < 8; ++a) p[a] = g * Eigen::Vector3d(kHexCorners[a][0], kHexCorners[a][1], kHexCorners[a][2]);
    return p;
  }();
  return points;
}

ElementStatus hex8_evaluate(const Material& m, const Matrix83d& X, const Matrix83d& u, Vector24d* f,
                            Matrix24d* K, double* energy) {
  if (f) f->setZero();
  if (K) K->setZero();
  if (energy) *energy = 0.0;
  Eigen::Matrix3d S;
  Matrix6d D;
  for (const auto& xi : hex8_gauss_points()) {
    const Matrix83d dNdxi = hex8_shape_gradient(xi);
    const Eigen::Matrix3d J = X.transpose() * dNdxi;  // J_ij = dX_i / dxi_j
    const double detJ = J.determinant();
    if (!(detJ > 0.0)) return ElementStatus::DegenerateReference;
    const Matrix83d dN = dNdxi * J.inverse();  // dN_a/dX_j
    const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + u.transpose() * dN;
    double psi = 0.0;
    if (!evaluate_material(m, F, S, K ? &D : nullptr, energy ? &psi : nullptr)) return ElementStatus::Inverted;
    if (energy) *energy += psi * detJ;
    add_tl_point<8>(dN, F, S, K ? &D : nullptr, detJ, f, K);  // B_L, K_L, K_NL: tl_point.hpp
  }
  return ElementStatus::Ok;
}

bool hex8_average_stress(const Material& m, const Matrix83d& X, const Matrix83d& u, Eigen::Matrix3d& F,
                         Eigen::Matrix3d& S) {
  F.setZero();
  S.setZero();
  double volume = 0.0;
  for (const auto& xi : hex8_gauss_points()) {
    const Matrix83d dNdxi = hex8_shape_gradient(xi);
    const Eigen::Matrix3d J = X.transpose() * dNdxi;
    const double detJ = J.determinant();
    if (!(detJ > 0.0)) return false;
    const Eigen::Matrix3d Fg = Eigen::Matrix3d::Identity() + u.transpose() * (dNdxi * J.inverse());
    Eigen::Matrix3d Sg;
    if (!evaluate_material(m, Fg, Sg, nullptr, nullptr)) return false;
    F += detJ * Fg;
    S += detJ * Sg;
    volume += detJ;
  }
  F /= volume;
  S /= volume;
  return true;
}

}  // namespace tetfsi::solid::hex
