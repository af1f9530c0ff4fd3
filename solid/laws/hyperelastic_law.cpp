#include "solid/laws/hyperelastic_law.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>

namespace tetfsi::solid {
namespace {

using Mat3 = Eigen::Matrix3d;
using Mat9 = Eigen::Matrix<double, 9, 9>;

// Stable neo-Hookean constants: lambda' = lambda + mu, a = 1 + mu / lambda' (Smith et al. 2018).
// Expanding Psi to second order in H = F - I gives mu |sym H|^2 + lambda/2 tr(H)^2.
struct StableConstants {
  double lambda_prime, a;
};
StableConstants stable_constants(const HyperelasticParams& p) {
  const double lp = p.lambda + p.mu;
  return {lp, 1.0 + p.mu / lp};
}

double bulk_modulus(const HyperelasticParams& p) { return p.lambda + 2.0 * p.mu / 3.0; }

// d cof(F) in direction dF: derivative of the column cross products (the Hessian of J applied to dF).
Mat3 cofactor_differential(const Mat3& F, const Mat3& dF) {
  Mat3 dcof;
  dcof.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
  dcof.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
  dcof.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
  return dcof;
}

// Quantities of the laws written with F^{-T} (J > 0), computed once per F.
struct InverseForms {
  double J, lnJ, I1;
  Mat3 G;  // F^{-T}
  explicit InverseForms(const Mat3& F)
      : J(F.determinant()), lnJ(std::log(J)), I1(F.squaredNorm()), G(F.inverse().transpose()) {}
};

// dP of Bonet & Wood: mu dF + lambda (G:dF) G - (lambda ln J - mu) G dF^T G   (d G = -G dF^T G).
Mat3 bonet_wood_differential(const HyperelasticParams& p, const InverseForms& f, const Mat3& dF) {
  return p.mu * dF + p.lambda * f.G.cwiseProduct(dF).sum() * f.G -
         (p.lambda * f.lnJ - p.mu) * (f.G * dF.transpose() * f.G);
}

// dP of the split law, P = mu c (F - I_1/3 G) + K J (J - 1) G with c = J^{-2/3}:
// dc = -2/3 c (G:dF), dI_1 = 2 F:dF, dJ = J G:dF.
Mat3 split_differential(const HyperelasticParams& p, const InverseForms& f, const Mat3& F, const Mat3& dF) {
  const double K = bulk_modulus(p);
  const double c = std::pow(f.J, -2.0 / 3.0);
  const double GdF = f.G.cwiseProduct(dF).sum(), FdF = F.cwiseProduct(dF).sum();
  const Mat3 GdFG = f.G * dF.transpose() * f.G;
  const Mat3 iso = -2.0 / 3.0 * c * GdF * (F - f.I1 / 3.0 * f.G) +
                   c * (dF - 2.0 / 3.0 * FdF * f.G + f.I1 / 3.0 * GdFG);
  return p.mu * iso + K * (f.J * (2.0 * f.J - 1.0) * GdF * f.G - f.J * (f.J - 1.0) * GdFG);
}

}  // namespace

std::optional<HyperelasticLaw> parse_hyperelastic_law(const std::string& name) {
  if (name == "stvk") return HyperelasticLaw::kStVK;
  if (name == "neohookean_bonet_wood") return HyperelasticLaw::kNeoHookeanBonetWood;
  if (name == "neohookean_stable" || name == "neohookean") return HyperelasticLaw::kNeoHookeanStable;
  if (name == "neohookean_split") return HyperelasticLaw::kNeoHookeanSplit;
  return std::nullopt;
}

const char* hyperelastic_law_name(HyperelasticLaw law) {
  switch (law) {
    case HyperelasticLaw::kStVK: return "stvk";
    case HyperelasticLaw::kNeoHookeanBonetWood: return "neohookean_bonet_wood";
    case HyperelasticLaw::kNeoHookeanStable: return "neohookean_stable";
    case HyperelasticLaw::kNeoHookeanSplit: return "neohookean_split";
  }
  return "?";
}

bool law_defined_at(HyperelasticLaw law, double J) {
  if (law == HyperelasticLaw::kStVK || law == HyperelasticLaw::kNeoHookeanStable) return std::isfinite(J);
  return J > 0.0;
}

Mat3 cofactor(const Mat3& F) {
  Mat3 c;
  c.col(0) = F.col(1).cross(F.col(2));
  c.col(1) = F.col(2).cross(F.col(0));
  c.col(2) = F.col(0).cross(F.col(1));
  return c;
}

double energy_density(const HyperelasticParams& p, const Mat3& F) {
  switch (p.law) {
    case HyperelasticLaw::kStVK: {
      const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
      const double tr = E.trace();
      return 0.5 * p.lambda * tr * tr + p.mu * E.squaredNorm();
    }
    case HyperelasticLaw::kNeoHookeanBonetWood: {
      const double lnJ = std::log(F.determinant());
      return 0.5 * p.mu * (F.squaredNorm() - 3.0) - p.mu * lnJ + 0.5 * p.lambda * lnJ * lnJ;
    }
    case HyperelasticLaw::kNeoHookeanStable: {
      const auto [lp, a] = stable_constants(p);
      const double J = F.determinant();
      return 0.5 * p.mu * (F.squaredNorm() - 3.0) + 0.5 * lp * ((J - a) * (J - a) - (1 - a) * (1 - a));
    }
    case HyperelasticLaw::kNeoHookeanSplit: {
      const double J = F.determinant();
      return 0.5 * p.mu * (std::pow(J, -2.0 / 3.0) * F.squaredNorm() - 3.0) +
             0.5 * bulk_modulus(p) * (J - 1.0) * (J - 1.0);
    }
  }
  return 0.0;
}

Mat3 first_piola(const HyperelasticParams& p, const Mat3& F) {
  switch (p.law) {
    case HyperelasticLaw::kStVK: {
      const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
      return F * (p.lambda * E.trace() * Mat3::Identity() + 2.0 * p.mu * E);
    }
    case HyperelasticLaw::kNeoHookeanBonetWood: {
      const InverseForms f(F);
      return p.mu * F + (p.lambda * f.lnJ - p.mu) * f.G;
    }
    case HyperelasticLaw::kNeoHookeanStable: {
      const auto [lp, a] = stable_constants(p);
      return p.mu * F + lp * (F.determinant() - a) * cofactor(F);
    }
    case HyperelasticLaw::kNeoHookeanSplit: {
      const InverseForms f(F);
      return p.mu * std::pow(f.J, -2.0 / 3.0) * (F - f.I1 / 3.0 * f.G) + bulk_modulus(p) * f.J * (f.J - 1.0) * f.G;
    }
  }
  return Mat3::Zero();
}

Mat3 first_piola_differential(const HyperelasticParams& p, const Mat3& F, const Mat3& dF) {
  switch (p.law) {
    case HyperelasticLaw::kStVK: {
      const Mat3 I = Mat3::Identity();
      const Mat3 E = 0.5 * (F.transpose() * F - I);
      const Mat3 S = p.lambda * E.trace() * I + 2.0 * p.mu * E;
      const Mat3 dE = 0.5 * (dF.transpose() * F + F.transpose() * dF);
      return dF * S + F * (p.lambda * dE.trace() * I + 2.0 * p.mu * dE);  // dF S: geometric stiffness
    }
    case HyperelasticLaw::kNeoHookeanBonetWood: return bonet_wood_differential(p, InverseForms(F), dF);
    case HyperelasticLaw::kNeoHookeanStable: {
      const auto [lp, a] = stable_constants(p);
      const Mat3 cof = cofactor(F);
      return p.mu * dF + lp * (cof.cwiseProduct(dF).sum() * cof + (F.determinant() - a) * cofactor_differential(F, dF));
    }
    case HyperelasticLaw::kNeoHookeanSplit: return split_differential(p, InverseForms(F), F, dF);
  }
  return Mat3::Zero();
}

Mat9 first_piola_tangent(const HyperelasticParams& p, const Mat3& F) {
  Mat9 C;
  switch (p.law) {
    case HyperelasticLaw::kStVK: {
      const Mat3 I = Mat3::Identity();
      const Mat3 E = 0.5 * (F.transpose() * F - I);
      const Mat3 S = p.lambda * E.trace() * I + 2.0 * p.mu * E;
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
          // dF = e_a e_b^T: dF S = e_a S.row(b); dE = (F.row(a)^T e_b^T + e_b F.row(a)) / 2.
          Mat3 dE = Mat3::Zero();
          dE.col(b) += 0.5 * F.row(a).transpose();
          dE.row(b) += 0.5 * F.row(a);
          Mat3 dP = F * (p.lambda * F(a, b) * I + 2.0 * p.mu * dE);
          dP.row(a) += S.row(b);
          C.col(a + 3 * b) = dP.reshaped();
        }
      return C;
    }
    case HyperelasticLaw::kNeoHookeanStable: {
      const auto [lp, a0] = stable_constants(p);
      const Mat3 cof = cofactor(F);
      const double J = F.determinant();
      const Eigen::Matrix<double, 9, 1> g = cof.reshaped();
      C = lp * g * g.transpose();
      C.diagonal().array() += p.mu;
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
          Mat3 dF = Mat3::Zero();
          dF(a, b) = 1.0;
          C.col(a + 3 * b) += lp * (J - a0) * cofactor_differential(F, dF).reshaped();
        }
      return C;
    }
    case HyperelasticLaw::kNeoHookeanBonetWood:
    case HyperelasticLaw::kNeoHookeanSplit: {
      const InverseForms f(F);
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
          Mat3 dF = Mat3::Zero();
          dF(a, b) = 1.0;
          const Mat3 dP = p.law == HyperelasticLaw::kNeoHookeanBonetWood ? bonet_wood_differential(p, f, dF)
                                                                          : split_differential(p, f, F, dF);
          C.col(a + 3 * b) = dP.reshaped();
        }
      return C;
    }
  }
  return Mat9::Zero();
}

}  // namespace tetfsi::solid
