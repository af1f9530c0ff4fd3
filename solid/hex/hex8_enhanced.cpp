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

/// The element at node displacements u and mode amplitudes A (row m = alpha_m): all 33 dofs
/// (N = 11), or only the modes' residual h and K_aa (N = 3: rows 8-10 of the gradients, whose B_L
/// columns and K_NL block need nothing else), the cheap evaluation of the local Newton.
template <int N>
ElementStatus evaluate(const Material& m, const Geometry& g, const Matrix83d& u, const Eigen::Matrix3d& A,
                       Eigen::Matrix<double, 3 * N, 1>& f, Eigen::Matrix<double, 3 * N, 3 * N>& K, double* energy) {
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
    const Eigen::Matrix<double, N, 3> rows = g.grad[q].template bottomRows<N>();
    add_tl_point<N>(rows, F, S, &D, g.detJ[q], &f, &K);
  }
  return ElementStatus::Ok;
}

/// Newton on h(u, alpha) = 0 from alpha = 0; f, K of all 33 dofs at the converged alpha.
ElementStatus solve_modes(const Material& m, const Geometry& g, const Matrix83d& u, Eigen::Matrix3d& A,
                          Vector33d& f, Matrix33x33d& K, double* energy) {
  A.setZero();
  // Converged when the step falls below 1e-10 of the element's relative nodal displacement (or
  // of alpha), or stops falling at a round-off floor below 1e-6 of it: S comes from E = (C - I)/2,
  // which keeps only ~1e-16 / |E| of its digits (1e-10 at a strain of 1e-6).
  const double scale = (u.rowwise() - u.row(0)).cwiseAbs().maxCoeff();
  double previous = std::numeric_limits<double>::infinity();
  Eigen::Matrix<double, 9, 1> h;
  Eigen::Matrix<double, 9, 9> Kaa;
  for (int it = 0;; ++it) {
    if (it == 30) return ElementStatus::Inverted;
    const ElementStatus s = evaluate<3>(m, g, u, A, h, Kaa, nullptr);
    if (s != ElementStatus::Ok) return s;
    const Eigen::Matrix<double, 9, 1> step = -Kaa.partialPivLu().solve(h);
    if (!step.allFinite()) return ElementStatus::Inverted;
    const double size = step.lpNorm<Eigen::Infinity>(), ref = std::max(scale, A.cwiseAbs().maxCoeff());
    if (size <= 1e-10 * ref || (size > 0.25 * previous && size <= 1e-6 * ref)) break;
    previous = size;
    for (int r = 0; r < 3; ++r) A.row(r) += step.segment<3>(3 * r).transpose();
  }
  return evaluate<11>(m, g, u, A, f, K, energy);
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
