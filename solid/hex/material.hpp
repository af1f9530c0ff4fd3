#pragma once
/// @file material.hpp
/// Hyperelastic laws for the Total Lagrangian hex8 element, written in terms of the
/// Green-Lagrange strain E = (C - I)/2, C = F^T F, and the 2nd Piola-Kirchhoff stress S = dpsi/dE.
///
/// Voigt order (as in Bathe 1996, sec. 6.3.2, matrix B_L): [xx, yy, zz, xy, yz, zx]; strains carry
/// engineering shears (2 E_xy, ...), stresses the tensor components (S_xy, ...), so that
/// S_voigt . dE_voigt = S : dE and D = dS_voigt / dE_voigt is symmetric.
#include <Eigen/Core>

#include "solid/laws/hyperelastic_law.hpp"

namespace tetfsi::solid::hex {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// The laws shared by every element (solid/laws/hyperelastic_law.hpp): St. Venant-Kirchhoff and the
/// three neo-Hookean forms (Bonet & Wood, stable, isochoric/volumetric split).
using MaterialLaw = HyperelasticLaw;

struct Material {
  MaterialLaw law = MaterialLaw::kStVK;
  double youngs_modulus = 1e6;  ///< E [Pa]
  double poisson_ratio = 0.3;   ///< nu [-], in (-1, 0.5)
  double density = 1000.0;      ///< rho [kg/m^3] (reference configuration)

  double lame_lambda() const;  ///< lambda = E nu / ((1 + nu)(1 - 2 nu)) [Pa]
  double lame_mu() const;      ///< mu = E / (2 (1 + nu)) [Pa]
  /// Throws std::invalid_argument naming the bad parameter.
  void validate() const;
};

/// Stress, tangent and energy density at a deformation gradient F, from the law's P(F) and dP/dF:
/// S = F^{-1} P, and, since dP = dF S + F dS with dS = C : dE, dE = sym(F^T dF),
/// C_IJKL = F^{-1}_Ii F^{-1}_Kk (dP_iJ/dF_kL - delta_ik S_LJ)  (Bathe 1996, sec. 6.3.2 notation:
/// D(a, b) = C_IJKL for the Voigt pairs a = (I, J), b = (K, L)). StVK's D is the constant linear-elastic matrix.
/// @param F       deformation gradient dx/dX [-]
/// @param S       out: 2nd Piola-Kirchhoff stress [Pa]
/// @param D       out (optional): material tangent dS/dE in Voigt form [Pa]
/// @param psi     out (optional): strain energy density per reference volume [J/m^3]
/// @return false if det F <= 0 (inverted material point): the element cannot use it
bool evaluate_material(const Material& m, const Eigen::Matrix3d& F, Eigen::Matrix3d& S, Matrix6d* D,
                       double* psi);

/// Voigt index pairs [xx, yy, zz, xy, yz, zx].
inline constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};

/// Cauchy stress sigma = F S F^T / det F [Pa].
Eigen::Matrix3d cauchy_stress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& S);

}  // namespace tetfsi::solid::hex
