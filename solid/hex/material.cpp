#include "solid/hex/material.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "support/number_text.hpp"

namespace tetfsi::solid::hex {

double Material::lame_lambda() const {
  return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}
double Material::lame_mu() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }

void Material::validate() const {
  if (!(youngs_modulus > 0.0) || !std::isfinite(youngs_modulus)) {
    throw std::invalid_argument("hex material: Young's modulus must be > 0, got " +
                                number_text(youngs_modulus));
  }
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5)) {
    throw std::invalid_argument("hex material: Poisson ratio must lie in (-1, 0.5), got " +
                                number_text(poisson_ratio));
  }
  if (!(density > 0.0) || !std::isfinite(density)) {
    throw std::invalid_argument("hex material: density must be > 0, got " + number_text(density));
  }
}

bool evaluate_material(const Material& m, const Eigen::Matrix3d& F, Eigen::Matrix3d& S, Matrix6d* D,
                       double* psi) {
  const double J = F.determinant();
  if (!(J > 0.0)) return false;
  const double lambda = m.lame_lambda();
  const double mu = m.lame_mu();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d C = F.transpose() * F;
  if (m.law == MaterialLaw::StVenantKirchhoff) {
    const Eigen::Matrix3d E = 0.5 * (C - I);
    const double trE = E.trace();
    S = lambda * trE * I + 2.0 * mu * E;
    if (psi) *psi = 0.5 * lambda * trE * trE + mu * E.cwiseAbs2().sum();
    if (D) {
      D->setZero();
      D->topLeftCorner<3, 3>().setConstant(lambda);
      for (int a = 0; a < 3; ++a) (*D)(a, a) += 2.0 * mu;
      for (int a = 3; a < 6; ++a) (*D)(a, a) = mu;
    }
    return true;
  }
  const Eigen::Matrix3d Ci = C.inverse();
  const double lnJ = std::log(J);
  S = mu * (I - Ci) + lambda * lnJ * Ci;
  if (psi) *psi = 0.5 * mu * (C.trace() - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
  if (D) {
    const double c = mu - lambda * lnJ;
    for (int a = 0; a < 6; ++a) {
      const int i = kVoigt[a][0], j = kVoigt[a][1];
      for (int b = 0; b < 6; ++b) {
        const int k = kVoigt[b][0], l = kVoigt[b][1];
        (*D)(a, b) = lambda * Ci(i, j) * Ci(k, l) + c * (Ci(i, k) * Ci(j, l) + Ci(i, l) * Ci(j, k));
      }
    }
  }
  return true;
}

Eigen::Matrix3d cauchy_stress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& S) {
  return F * S * F.transpose() / F.determinant();
}

}  // namespace tetfsi::solid::hex
