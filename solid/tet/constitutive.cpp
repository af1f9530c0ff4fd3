#include "solid/tet/constitutive.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "solid/solid_error.hpp"

namespace tetfsi::solid {
namespace {

// Stable neo-Hookean reparameterization: lambda' = lambda + mu and a = 1 + mu / lambda'
// give the same small-strain response as linear elasticity with (lambda, mu): expanding
// Psi to second order in H = F - I gives mu |sym H|^2 + lambda/2 tr(H)^2.
struct NeoHookeanConstants {
  double lambda_prime;
  double a;
};
NeoHookeanConstants nh_constants(const ConstitutiveParams& p) {
  const double lp = p.lambda + p.mu;
  return {lp, 1.0 + p.mu / lp};
}

}  // namespace

void TetMaterial::validate() const {
  if (!(youngs_modulus > 0)) throw SolidError("material: youngs_modulus must be > 0 [Pa]");
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    throw SolidError("material: poisson_ratio must lie in (-1, 0.5)");
  if (!(density > 0)) throw SolidError("material: density must be > 0 [kg/m^3]");
  if (!(rayleigh_alpha >= 0) || !(rayleigh_beta >= 0))
    throw SolidError("material: rayleigh_alpha and rayleigh_beta must be >= 0");
}

Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {
  Eigen::Matrix3d c;
  c.col(0) = F.col(1).cross(F.col(2));
  c.col(1) = F.col(2).cross(F.col(0));
  c.col(2) = F.col(0).cross(F.col(1));
  return c;
}

double energy_density(const ConstitutiveParams& p, const Eigen::Matrix3d& F) {
  if (p.law == ConstitutiveLaw::kStVK) {
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    const double tr = E.trace();
    return 0.5 * p.lambda * tr * tr + p.mu * E.squaredNorm();
  }
  const auto [lp, a] = nh_constants(p);
  const double J = F.determinant();
  return 0.5 * p.mu * (F.squaredNorm() - 3.0) + 0.5 * lp * ((J - a) * (J - a) - (1 - a) * (1 - a));
}

Eigen::Matrix3d first_piola(const ConstitutiveParams& p, const Eigen::Matrix3d& F) {
  if (p.law == ConstitutiveLaw::kStVK) {
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    const Eigen::Matrix3d S = p.lambda * E.trace() * Eigen::Matrix3d::Identity() + 2.0 * p.mu * E;
    return F * S;
  }
  const auto [lp, a] = nh_constants(p);
  return p.mu * F + lp * (F.determinant() - a) * cofactor(F);
}

Eigen::Matrix3d first_piola_differential(const ConstitutiveParams& p, const Eigen::Matrix3d& F,
                                         const Eigen::Matrix3d& dF) {
  if (p.law == ConstitutiveLaw::kStVK) {
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - I);
    const Eigen::Matrix3d S = p.lambda * E.trace() * I + 2.0 * p.mu * E;
    const Eigen::Matrix3d dE = 0.5 * (dF.transpose() * F + F.transpose() * dF);
    const Eigen::Matrix3d dS = p.lambda * dE.trace() * I + 2.0 * p.mu * dE;
    return dF * S + F * dS;
  }
  const auto [lp, a] = nh_constants(p);
  const Eigen::Matrix3d cof = cofactor(F);
  // d cof(F): derivative of the column cross products.
  Eigen::Matrix3d dcof;
  dcof.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
  dcof.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
  dcof.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
  const double J = F.determinant();
  return p.mu * dF + lp * (cof.cwiseProduct(dF).sum() * cof + (J - a) * dcof);
}

Eigen::Matrix<double, 9, 9> first_piola_tangent(const ConstitutiveParams& p, const Eigen::Matrix3d& F) {
  Eigen::Matrix<double, 9, 9> C;
  if (p.law == ConstitutiveLaw::kStVK) {
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - I);
    const Eigen::Matrix3d S = p.lambda * E.trace() * I + 2.0 * p.mu * E;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        // dF = e_a e_b^T: dF S = e_a S.row(b); dE = (F.row(a)^T e_b^T + e_b F.row(a)) / 2.
        Eigen::Matrix3d dE = Eigen::Matrix3d::Zero();
        dE.col(b) += 0.5 * F.row(a).transpose();
        dE.row(b) += 0.5 * F.row(a);
        Eigen::Matrix3d dP = F * (p.lambda * F(a, b) * I + 2.0 * p.mu * dE);
        dP.row(a) += S.row(b);
        C.col(a + 3 * b) = dP.reshaped();
      }
    return C;
  }
  const auto [lp, a0] = nh_constants(p);
  const Eigen::Matrix3d cof = cofactor(F);
  const double J = F.determinant();
  const Eigen::Matrix<double, 9, 1> g = cof.reshaped();
  C = lp * g * g.transpose();
  C.diagonal().array() += p.mu;
  // (J - a) d cof(F): the Hessian of J. Column (a, b): d cof for dF = e_a e_b^T.
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF(a, b) = 1.0;
      Eigen::Matrix3d dcof;
      dcof.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
      dcof.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
      dcof.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
      C.col(a + 3 * b) += lp * (J - a0) * dcof.reshaped();
    }
  return C;
}

Eigen::Matrix3d cauchy_stress(const ConstitutiveParams& p, const Eigen::Matrix3d& F) {
  const double J = F.determinant();
  const Eigen::Matrix3d PFt = first_piola(p, F) * F.transpose();
  return J > 0 ? Eigen::Matrix3d(PFt / J) : PFt;
}

}  // namespace tetfsi::solid
