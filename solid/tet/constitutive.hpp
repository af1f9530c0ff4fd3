#pragma once
/// @file constitutive.hpp
/// Hyperelastic energy density Psi(F), first Piola-Kirchhoff stress P = dPsi/dF and its
/// directional derivative dP = (d^2 Psi / dF^2) : dF for the laws of material.hpp.
/// All quantities per unit reference volume: Psi [J/m^3], P [Pa].
#include <Eigen/Core>

#include "solid/tet/material.hpp"

namespace tetfsi::solid {

/// Lame parameters and law, precomputed from a TetMaterial.
struct ConstitutiveParams {
  ConstitutiveLaw law = ConstitutiveLaw::kStVK;
  double lambda = 0;  ///< [Pa]
  double mu = 0;      ///< [Pa]
  static ConstitutiveParams from(const TetMaterial& m) { return {m.law, m.lambda(), m.mu()}; }
};

/// Strain energy density Psi(F) [J/m^3]; zero at F = I.
/// StVK: Psi = lambda/2 tr(E)^2 + mu E:E with E = (F^T F - I)/2.
/// Stable neo-Hookean: Psi = mu/2 (I_C - 3) + lambda'/2 [(J - a)^2 - (1 - a)^2].
double energy_density(const ConstitutiveParams& p, const Eigen::Matrix3d& F);

/// First Piola-Kirchhoff stress P = dPsi/dF [Pa].
/// StVK: P = F S, S = lambda tr(E) I + 2 mu E (O'Brien & Hodgins 1999, eq. 3-4 with the
/// Green strain). Stable neo-Hookean: P = mu F + lambda' (J - a) cof(F), cof(F) = dJ/dF.
Eigen::Matrix3d first_piola(const ConstitutiveParams& p, const Eigen::Matrix3d& F);

/// Differential dP at F in direction dF (the consistent tangent applied to dF) [Pa].
/// StVK: dP = dF S + F dS, dS = lambda tr(dE) I + 2 mu dE, dE = (dF^T F + F^T dF)/2;
/// the dF S term is the geometric stiffness.
Eigen::Matrix3d first_piola_differential(const ConstitutiveParams& p, const Eigen::Matrix3d& F,
                                         const Eigen::Matrix3d& dF);

/// Second Piola-Kirchhoff stress S = F^{-1} P [Pa] for StVK (exact), and the Cauchy stress
/// sigma = P F^T / J [Pa] for output (requires J > 0; returns P F^T otherwise).
Eigen::Matrix3d cauchy_stress(const ConstitutiveParams& p, const Eigen::Matrix3d& F);

/// Cofactor matrix cof(F) = dJ/dF, columns [f1 x f2, f2 x f0, f0 x f1] for F = [f0 f1 f2];
/// polynomial in F, valid for singular and inverted F.
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F);

}  // namespace tetfsi::solid
