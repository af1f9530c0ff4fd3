// The four hyperelastic laws (solid/laws/hyperelastic_law.hpp) on both elements: the tet's view
// (P(F) and its 9 x 9 tangent dP/dF, solid/tet/constitutive.hpp) and the hex8's (S, D = dS/dE in
// Voigt form, solid/hex/material.hpp). For each law and element:
//  (a) the stress is the derivative of the energy (central differences, 1e-6 relative);
//  (b) the tangent is the derivative of the stress (central differences, 1e-6 relative);
//  (c) zero stress at F = I;
//  (d) small strain: the linear-elastic stress lambda tr(eps) I + 2 mu eps of E, nu to 1e-6 relative,
//      and the tangent at F = I equals the linear-elastic tensor to 1e-10;
//  (e) uniaxial strain F = diag(s, 1, 1), s = 1.3 and 0.7: P_11 and P_22 against each law's closed form.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <string>
#include <vector>

#include "solid/hex/material.hpp"
#include "solid/laws/hyperelastic_law.hpp"
#include "solid/tet/constitutive.hpp"

using namespace tetfsi::solid;
using Eigen::Matrix3d;

namespace {

constexpr double kE = 1e6, kNu = 0.3;
const double kLambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), kMu = kE / (2 * (1 + kNu));
const std::vector<HyperelasticLaw> kLaws = {HyperelasticLaw::kStVK, HyperelasticLaw::kNeoHookeanBonetWood,
                                            HyperelasticLaw::kNeoHookeanStable, HyperelasticLaw::kNeoHookeanSplit};

// A general deformation gradient (stretch, shear and rotation; J = 1.17).
Matrix3d general_F() {
  Matrix3d F;
  F << 1.2, 0.1, -0.05, 0.08, 0.9, 0.12, -0.1, 0.05, 1.1;
  return F;
}

ConstitutiveParams tet_params(HyperelasticLaw law) {
  TetMaterial m;
  m.youngs_modulus = kE;
  m.poisson_ratio = kNu;
  m.law = law;
  return ConstitutiveParams::from(m);
}

hex::Material hex_material(HyperelasticLaw law) {
  hex::Material m;
  m.youngs_modulus = kE;
  m.poisson_ratio = kNu;
  m.law = law;
  return m;
}

struct HexState {
  Matrix3d S;
  hex::Matrix6d D;
  double psi = 0;
};
HexState hex_eval(HyperelasticLaw law, const Matrix3d& F) {
  HexState s;
  EXPECT_TRUE(hex::evaluate_material(hex_material(law), F, s.S, &s.D, &s.psi));
  return s;
}

// Green strain increment dE = sym(F^T dF) in the hex's Voigt form (engineering shears).
hex::Vector6d voigt_strain(const Matrix3d& F, const Matrix3d& dF) {
  const Matrix3d dE = 0.5 * (F.transpose() * dF + dF.transpose() * F);
  hex::Vector6d v;
  for (int a = 0; a < 6; ++a) {
    const int i = hex::kVoigt[a][0], j = hex::kVoigt[a][1];
    v(a) = i == j ? dE(i, j) : 2.0 * dE(i, j);
  }
  return v;
}
hex::Vector6d voigt_stress(const Matrix3d& S) {
  hex::Vector6d v;
  for (int a = 0; a < 6; ++a) v(a) = S(hex::kVoigt[a][0], hex::kVoigt[a][1]);
  return v;
}

Matrix3d unit(int a, int b) {
  Matrix3d d = Matrix3d::Zero();
  d(a, b) = 1.0;
  return d;
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

// Closed forms of uniaxial strain F = diag(s, 1, 1) (J = s): {P_11, P_22}, from each energy by hand.
std::pair<double, double> uniaxial_strain(HyperelasticLaw law, double s) {
  const double l = kLambda, m = kMu, K = kLambda + 2 * kMu / 3;
  switch (law) {
    case HyperelasticLaw::kStVK: {  // E_11 = (s^2 - 1)/2, S = lambda E_11 I + 2 mu E
      const double e = 0.5 * (s * s - 1);
      return {s * (l + 2 * m) * e, l * e};
    }
    case HyperelasticLaw::kNeoHookeanBonetWood:  // P = mu (F - F^-T) + lambda ln J F^-T
      return {m * (s - 1 / s) + l * std::log(s) / s, l * std::log(s)};
    case HyperelasticLaw::kNeoHookeanStable: {  // P = mu F + lambda' (J - a) cof F, cof = diag(1, s, s)
      const double lp = l + m, a = 1 + m / lp;
      return {m * s + lp * (s - a), m + lp * (s - a) * s};
    }
    case HyperelasticLaw::kNeoHookeanSplit: {  // P = mu J^-2/3 (F - I1/3 F^-T) + K J (J - 1) F^-T
      const double c = std::pow(s, -2.0 / 3.0), I1 = s * s + 2;
      return {m * c * (s - I1 / (3 * s)) + K * (s - 1), m * c * (1 - I1 / 3) + K * s * (s - 1)};
    }
  }
  return {0, 0};
}

}  // namespace

TEST(HyperelasticLaws, NamesParseAndNeoHookeanIsTheStableLaw) {
  for (auto law : kLaws) EXPECT_EQ(parse_hyperelastic_law(hyperelastic_law_name(law)), law);
  EXPECT_EQ(parse_hyperelastic_law("neohookean"), HyperelasticLaw::kNeoHookeanStable);
  EXPECT_FALSE(parse_hyperelastic_law("mooney_rivlin").has_value());
}

TEST(HyperelasticLaws, TetStressIsEnergyDerivativeAndTangentIsStressDerivative) {
  const Matrix3d F = general_F();
  const double h = 1e-6;
  for (auto law : kLaws) {
    const auto p = tet_params(law);
    Matrix3d P_fd;
    Eigen::Matrix<double, 9, 9> C_fd;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const Matrix3d d = h * unit(a, b);
        P_fd(a, b) = (energy_density(p, F + d) - energy_density(p, F - d)) / (2 * h);
        C_fd.col(a + 3 * b) = ((first_piola(p, F + d) - first_piola(p, F - d)) / (2 * h)).reshaped();
      }
    const Eigen::Matrix<double, 9, 9> C = first_piola_tangent(p, F);
    EXPECT_LT(rel(first_piola(p, F), P_fd), 1e-6) << hyperelastic_law_name(law);
    EXPECT_LT(rel(C, C_fd), 1e-6) << hyperelastic_law_name(law);
    EXPECT_LT(rel(C, C.transpose()), 1e-12) << hyperelastic_law_name(law);  // a Hessian
    // The differential equals the tangent applied to dF.
    const Matrix3d dF = 0.3 * unit(0, 1) - 0.2 * unit(2, 0) + 0.1 * unit(1, 1);
    const Eigen::Matrix<double, 9, 1> CdF = C * dF.reshaped();
    EXPECT_LT(rel(first_piola_differential(p, F, dF).reshaped(), CdF), 1e-12) << hyperelastic_law_name(law);
  }
}

TEST(HyperelasticLaws, HexStressIsEnergyDerivativeAndTangentIsStressDerivative) {
  const Matrix3d F = general_F();
  const double h = 1e-6;
  for (auto law : kLaws) {
    const HexState s = hex_eval(law, F);
    Matrix3d P_fd;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a)
        P_fd(a, b) = (hex_eval(law, F + h * unit(a, b)).psi - hex_eval(law, F - h * unit(a, b)).psi) / (2 * h);
    EXPECT_LT(rel(F * s.S, P_fd), 1e-6) << hyperelastic_law_name(law);  // P = F S
    EXPECT_LT(rel(s.D, s.D.transpose()), 1e-12) << hyperelastic_law_name(law);
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const Matrix3d dF = unit(a, b) + 0.3 * unit(b, a);
        const hex::Vector6d dS_fd =
            (voigt_stress(hex_eval(law, F + h * dF).S) - voigt_stress(hex_eval(law, F - h * dF).S)) / (2 * h);
        EXPECT_LT(rel(s.D * voigt_strain(F, dF), dS_fd), 1e-6) << hyperelastic_law_name(law) << ' ' << a << b;
      }
  }
}

TEST(HyperelasticLaws, ZeroStressAtRestAndLinearElasticLimit) {
  // Linear-elastic tangent lambda d_iJ d_kL + mu (d_ik d_JL + d_iL d_Jk) and its Voigt form.
  Eigen::Matrix<double, 9, 9> C_lin = Eigen::Matrix<double, 9, 9>::Zero();
  for (int J = 0; J < 3; ++J)
    for (int i = 0; i < 3; ++i)
      for (int L = 0; L < 3; ++L)
        for (int k = 0; k < 3; ++k)
          C_lin(i + 3 * J, k + 3 * L) = kLambda * (i == J) * (k == L) + kMu * ((i == k) * (J == L) + (i == L) * (J == k));
  hex::Matrix6d D_lin = hex::Matrix6d::Zero();
  D_lin.topLeftCorner<3, 3>().setConstant(kLambda);
  for (int a = 0; a < 3; ++a) D_lin(a, a) += 2 * kMu;
  for (int a = 3; a < 6; ++a) D_lin(a, a) = kMu;
  Matrix3d H;
  H << 0.3, -0.7, 0.2, 0.5, -0.4, 0.9, -0.1, 0.6, 0.8;
  const double eps = 1e-8;
  const Matrix3d e = 0.5 * eps * (H + H.transpose());
  const Matrix3d sigma = kLambda * e.trace() * Matrix3d::Identity() + 2 * kMu * e;
  const Matrix3d I = Matrix3d::Identity();
  for (auto law : kLaws) {
    const auto p = tet_params(law);
    EXPECT_LT(first_piola(p, I).norm(), 1e-12 * kE) << hyperelastic_law_name(law);
    EXPECT_LT(hex_eval(law, I).S.norm(), 1e-12 * kE) << hyperelastic_law_name(law);
    EXPECT_NEAR(energy_density(p, I), 0.0, 1e-12 * kE) << hyperelastic_law_name(law);
    EXPECT_LT(rel(first_piola(p, I + eps * H), sigma), 1e-6) << hyperelastic_law_name(law);
    EXPECT_LT(rel(hex_eval(law, I + eps * H).S, sigma), 1e-6) << hyperelastic_law_name(law);
    EXPECT_LT(rel(first_piola_tangent(p, I), C_lin), 1e-10) << hyperelastic_law_name(law);
    EXPECT_LT(rel(hex_eval(law, I).D, D_lin), 1e-10) << hyperelastic_law_name(law);
  }
}

TEST(HyperelasticLaws, UniaxialStrainMatchesClosedForms) {
  for (auto law : kLaws)
    for (double s : {1.3, 0.7}) {
      const Matrix3d F = Eigen::Vector3d(s, 1, 1).asDiagonal();
      const auto [P11, P22] = uniaxial_strain(law, s);
      const Matrix3d P = first_piola(tet_params(law), F);
      const Matrix3d S = hex_eval(law, F).S;
      const std::string what = std::string(hyperelastic_law_name(law)) + " s = " + std::to_string(s);
      EXPECT_NEAR(P(0, 0), P11, 1e-12 * kE) << what;
      EXPECT_NEAR(P(1, 1), P22, 1e-12 * kE) << what;
      EXPECT_NEAR(P(2, 2), P22, 1e-12 * kE) << what;
      EXPECT_NEAR(P(0, 1), 0.0, 1e-12 * kE) << what;
      EXPECT_NEAR(s * S(0, 0), P11, 1e-12 * kE) << what;  // P = F S
      EXPECT_NEAR(S(1, 1), P22, 1e-12 * kE) << what;
      std::printf("%-22s s = %.1f: P11 = %.6e Pa, P22 = %.6e Pa\n", hyperelastic_law_name(law), s, P11, P22);
    }
}
