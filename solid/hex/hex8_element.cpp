#include "solid/hex/hex8_element.hpp"

#include <Eigen/LU>
#include <cmath>

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
  Eigen::Matrix<double, 6, 24> BL;
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
    // B_L = B_L0 + B_L1(u), column (a, k): see the header.
    for (int a = 0; a < 8; ++a) {
      for (int k = 0; k < 3; ++k) {
        const int c = 3 * a + k;
        BL(0, c) = F(k, 0) * dN(a, 0);
        BL(1, c) = F(k, 1) * dN(a, 1);
        BL(2, c) = F(k, 2) * dN(a, 2);
        BL(3, c) = F(k, 0) * dN(a, 1) + F(k, 1) * dN(a, 0);
        BL(4, c) = F(k, 1) * dN(a, 2) + F(k, 2) * dN(a, 1);
        BL(5, c) = F(k, 2) * dN(a, 0) + F(k, 0) * dN(a, 2);
      }
    }
    Vector6d Sv;
    for (int v = 0; v < 6; ++v) Sv(v) = S(kVoigt[v][0], kVoigt[v][1]);
    if (f) f->noalias() += detJ * (BL.transpose() * Sv);
    if (K) {
      K->noalias() += detJ * (BL.transpose() * (D * BL));  // K_L
      // K_NL = B_NL^T blockdiag(S,S,S) B_NL: entry (a k, b l) = delta_kl dN_a . S dN_b.
      const Eigen::Matrix<double, 8, 8> G = detJ * (dN * S * dN.transpose());
      for (int a = 0; a < 8; ++a) {
        for (int b = 0; b < 8; ++b) {
          for (int k = 0; k < 3; ++k) (*K)(3 * a + k, 3 * b + k) += G(a, b);
        }
      }
    }
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
