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
  const HyperelasticParams p{m.law, m.lame_lambda(), m.lame_mu()};
  const Eigen::Matrix3d Finv = F.inverse();
  S = Finv * first_piola(p, F);
  S = 0.5 * (S + S.transpose()).eval();  // symmetric up to round-off
  if (psi) *psi = energy_density(p, F);
  if (!D) return true;
  if (m.law == MaterialLaw::kStVK) {  // dS/dE is constant: lambda I x I + 2 mu II
    D->setZero();
    D->topLeftCorner<3, 3>().setConstant(p.lambda);
    for (int a = 0; a < 3; ++a) (*D)(a, a) += 2.0 * p.mu;
    for (int a = 3; a < 6; ++a) (*D)(a, a) = p.mu;
    return true;
  }
  // B_iJkL = dP_iJ/dF_kL - delta_ik S_LJ, then C_IJKL = Finv_Ii Finv_Kk B_iJkL.
  Eigen::Matrix<double, 9, 9> B = first_piola_tangent(p, F);
  for (int i = 0; i < 3; ++i)
    for (int Jc = 0; Jc < 3; ++Jc)
      for (int L = 0; L < 3; ++L) B(i + 3 * Jc, i + 3 * L) -= S(L, Jc);
  for (int a = 0; a < 6; ++a) {
    const int I = kVoigt[a][0], Jc = kVoigt[a][1];
    for (int b = 0; b < 6; ++b) {
      const int K = kVoigt[b][0], L = kVoigt[b][1];
      double c = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) c += Finv(I, i) * Finv(K, k) * B(i + 3 * Jc, k + 3 * L);
      (*D)(a, b) = c;
    }
  }
  *D = 0.5 * (*D + D->transpose()).eval();
  return true;
}

Eigen::Matrix3d cauchy_stress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& S) {
  return F * S * F.transpose() / F.determinant();
}

}  // namespace tetfsi::solid::hex
