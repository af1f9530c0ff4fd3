#include "solid/hex/hex8_enhanced.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "solid/hex/tl_point.hpp"

namespace tetfsi::solid::hex {
namespace {

using Matrix113d = Eigen::Matrix<double, 11, 3>;
using Vector33d = Eigen::Matrix<double, 33, 1>;
using Matrix33x33d = Eigen::Matrix<double, 33, 33>;

/// Per Gauss point: rows 0-7 dN_a/dX, rows 8-10 the modes' G_m (header), and det J.
struct Geometry {
  std::array<Matrix113d, 8> grad;
  std::array<double, 8> detJ{};
  double volume = 0.0;
};

bool make_geometry(const Matrix83d& X, Geometry& g) {
  const Eigen::Matrix3d J0 = X.transpose() * hex8_shape_gradient(Eigen::Vector3d::Zero());
  const double j0 = J0.determinant();
  if (!(j0 > 0.0)) return false;
  const Eigen::Matrix3d J0inv = J0.inverse();
  for (int q = 0; q < 8; ++q) {
    const Eigen::Vector3d& xi = hex8_gauss_points()[q];
    const Matrix83d dNdxi = hex8_shape_gradient(xi);
    const Eigen::Matrix3d J = X.transpose() * dNdxi;
    const double detJ = J.determinant();
    if (!(detJ > 0.0)) return false;
    g.detJ[q] = detJ;
    g.volume += detJ;
    g.grad[q].topRows<8>() = dNdxi * J.inverse();
    // dM_m/dX_j = (j0/j) (dM_m/dxi_m) (J0^-1)_mj with dM_m/dxi_m = -2 xi_m.
    g.grad[q].bottomRows<3>() = (j0 / detJ) * (-2.0 * xi).asDiagonal() * J0inv;
  }
  return true;
}

/// The 33-dof element at node displacements u and mode amplitudes A (row m = alpha_m).
ElementStatus evaluate33(const Material& m, const Geometry& g, const Matrix83d& u, const Eigen::Matrix3d& A,
                         Vector33d& f, Matrix33x33d& K, double* energy) {
  f.setZero();
  K.setZero();
  if (energy) *energy = 0.0;
  Eigen::Matrix<double, 11, 3> U;
  U << u, A;
  Eigen::Matrix3d S;
  Matrix6d D;
  for (int q = 0; q < 8; ++q) {
    const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + U.transpose() * g.grad[q];
    double psi = 0.0;
    if (!evaluate_material(m, F, S, &D, energy ? &psi : nullptr)) return ElementStatus::Inverted;
    if (energy) *energy += psi * g.detJ[q];
    add_tl_point<11>(g.grad[q], F, S, &D, g.detJ[q], &f, &K);
  }
  return ElementStatus::Ok;
}

/// Newton on h(u, alpha) = 0 from alpha = 0; f, K at the converged alpha.
ElementStatus solve_modes(const Material& m, const Geometry& g, const Matrix83d& u, Eigen::Matrix3d& A,
                          Vector33d& f, Matrix33x33d& K, double* energy) {
  A.setZero();
  // Converged when the step falls below 1e-10 of the element's relative nodal displacement (or
  // of alpha), or stops falling at a round-off floor below 1e-6 of it: S comes from E = (C - I)/2,
  // which keeps only ~1e-16 / |E| of its digits (1e-10 at a strain of 1e-6).
  const double scale = (u.rowwise() - u.row(0)).cwiseAbs().maxCoeff();
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 30; ++it) {
    const ElementStatus s = evaluate33(m, g, u, A, f, K, energy);
    if (s != ElementStatus::Ok) return s;
    const Eigen::Matrix<double, 9, 1> step =
        -K.bottomRightCorner<9, 9>().partialPivLu().solve(f.tail<9>());
    if (!step.allFinite()) return ElementStatus::Inverted;
    const double size = step.lpNorm<Eigen::Infinity>(), ref = std::max(scale, A.cwiseAbs().maxCoeff());
    if (size <= 1e-10 * ref || (size > 0.25 * previous && size <= 1e-6 * ref)) return ElementStatus::Ok;
    previous = size;
    for (int r = 0; r < 3; ++r) A.row(r) += step.segment<3>(3 * r).transpose();
  }
  return ElementStatus::Inverted;
}

}  // namespace

ElementStatus hex8_enhanced_evaluate(const Material& m, const Matrix83d& X, const Matrix83d& u, Vector24d* f,
                                     Matrix24d* K, double* energy, Eigen::Matrix3d* alpha) {
  Geometry g;
  if (!make_geometry(X, g)) return ElementStatus::DegenerateReference;
  Eigen::Matrix3d A;
  Vector33d f33;
  Matrix33x33d K33;
  const ElementStatus s = solve_modes(m, g, u, A, f33, K33, energy);
  if (s != ElementStatus::Ok) return s;
  if (alpha) *alpha = A;
  if (!f && !K) return s;
  const auto Kaa = K33.bottomRightCorner<9, 9>().partialPivLu();
  const Eigen::Matrix<double, 9, 24> KaaInvKau = Kaa.solve(K33.bottomLeftCorner<9, 24>());
  if (f) *f = f33.head<24>() - K33.topRightCorner<24, 9>() * Kaa.solve(f33.tail<9>());
  if (K) *K = K33.topLeftCorner<24, 24>() - K33.topRightCorner<24, 9>() * KaaInvKau;
  return s;
}

bool hex8_enhanced_average_stress(const Material& m, const Matrix83d& X, const Matrix83d& u, Eigen::Matrix3d& F,
                                  Eigen::Matrix3d& S) {
  Geometry g;
  if (!make_geometry(X, g)) return false;
  Eigen::Matrix3d A;
  Vector33d f33;
  Matrix33x33d K33;
  if (solve_modes(m, g, u, A, f33, K33, nullptr) != ElementStatus::Ok) return false;
  Eigen::Matrix<double, 11, 3> U;
  U << u, A;
  F.setZero();
  S.setZero();
  for (int q = 0; q < 8; ++q) {
    const Eigen::Matrix3d Fq = Eigen::Matrix3d::Identity() + U.transpose() * g.grad[q];
    Eigen::Matrix3d Sq;
    if (!evaluate_material(m, Fq, Sq, nullptr, nullptr)) return false;
    F += g.detJ[q] * Fq;
    S += g.detJ[q] * Sq;
  }
  F /= g.volume;
  S /= g.volume;
  return true;
}

}  // namespace tetfsi::solid::hex
