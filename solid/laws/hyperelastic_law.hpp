#pragma once
/// @file hyperelastic_law.hpp
/// The hyperelastic laws of every solid element (tets and hex8): strain energy density Psi(F),
/// first Piola-Kirchhoff stress P = dPsi/dF and its exact tangent dP/dF, written once so that a law
/// named in a scene (`/solids/i/material/constitutive`) is the same law on every element.
/// Per unit reference volume: Psi [J/m^3], P [Pa]. Lame parameters lambda, mu [Pa] from E, nu;
/// J = det F, I_1 = tr(F^T F) = F:F, cof(F) = dJ/dF = J F^{-T}. Every law has zero stress at F = I
/// and the linear-elastic small-strain limit sigma = lambda tr(eps) I + 2 mu eps.
#include <Eigen/Core>
#include <optional>
#include <string>

namespace tetfsi::solid {

enum class HyperelasticLaw {
  /// St. Venant-Kirchhoff (O'Brien & Hodgins 1999, eqs. 3-4; Chentanez et al. 2006 sec. 3.2):
  /// Psi = lambda/2 tr(E)^2 + mu E:E, E = (F^T F - I)/2; P = F S, S = lambda tr(E) I + 2 mu E.
  /// Defined for any F, but softens and collapses under strong compression.
  kStVK,
  /// Compressible neo-Hookean of Bonet & Wood (*Nonlinear Continuum Mechanics*, 1997, eq. 6.28):
  /// Psi = mu/2 (I_1 - 3) - mu ln J + lambda/2 (ln J)^2; P = mu (F - F^{-T}) + lambda ln J F^{-T}.
  /// Defined for J > 0 only.
  kNeoHookeanBonetWood,
  /// Stable neo-Hookean (Smith, de Goes & Kim 2018, "Stable Neo-Hookean Flesh Simulation", the energy
  /// without its log(I_C + 1) term): Psi = mu/2 (I_1 - 3) + lambda'/2 [(J - a)^2 - (1 - a)^2],
  /// lambda' = lambda + mu, a = 1 + mu/lambda' (their reparameterisation: rest-stable, same small-strain
  /// lambda and mu); P = mu F + lambda' (J - a) cof(F). Polynomial in F: defined and smooth through
  /// J <= 0, pushing inverted elements back.
  kNeoHookeanStable,
  /// Isochoric/volumetric split neo-Hookean, the form of Abaqus (Theory Manual, sec. 4.6.1,
  /// "Hyperelastic material behavior", NEO HOOKE) and CalculiX (User's Manual, "Hyperelastic and
  /// hyperfoam materials"): Psi = C10 (Ibar_1 - 3) + (1/D1) (J - 1)^2, Ibar_1 = J^{-2/3} I_1,
  /// C10 = mu/2, D1 = 2/K, K = lambda + 2 mu/3 = E / (3 (1 - 2 nu)) the bulk modulus;
  /// P = mu J^{-2/3} (F - I_1/3 F^{-T}) + K J (J - 1) F^{-T}. Defined for J > 0 only.
  kNeoHookeanSplit,
};

/// Scene names: "stvk", "neohookean_bonet_wood", "neohookean_stable", "neohookean_split", and
/// "neohookean" = kNeoHookeanStable on every element (the inversion-robust one, which the dynamic
/// and coupled tet scenes need: their elements can invert in a step and must be pushed back).
std::optional<HyperelasticLaw> parse_hyperelastic_law(const std::string& name);
const char* hyperelastic_law_name(HyperelasticLaw law);

/// True if the law is defined at volume ratio J (kNeoHookeanStable and kStVK: any J; the others J > 0).
bool law_defined_at(HyperelasticLaw law, double J);

/// A law and its Lame parameters [Pa].
struct HyperelasticParams {
  HyperelasticLaw law = HyperelasticLaw::kStVK;
  double lambda = 0;  ///< [Pa]
  double mu = 0;      ///< [Pa]
};

/// Strain energy density Psi(F) [J/m^3]; zero at F = I.
double energy_density(const HyperelasticParams& p, const Eigen::Matrix3d& F);

/// First Piola-Kirchhoff stress P = dPsi/dF [Pa].
Eigen::Matrix3d first_piola(const HyperelasticParams& p, const Eigen::Matrix3d& F);

/// Differential dP = (d^2 Psi / dF^2) : dF at F in direction dF [Pa] (the exact tangent applied to dF).
Eigen::Matrix3d first_piola_differential(const HyperelasticParams& p, const Eigen::Matrix3d& F,
                                         const Eigen::Matrix3d& dF);

/// The exact tangent dP/dF as a 9 x 9 matrix over column-major vec(F): column a + 3b is vec(dP) for
/// dF = e_a e_b^T (symmetric: the Hessian of Psi). Same values as first_piola_differential.
Eigen::Matrix<double, 9, 9> first_piola_tangent(const HyperelasticParams& p, const Eigen::Matrix3d& F);

/// Cofactor matrix cof(F) = dJ/dF, columns [f1 x f2, f2 x f0, f0 x f1] for F = [f0 f1 f2];
/// polynomial in F, valid for singular and inverted F.
Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F);

}  // namespace tetfsi::solid
