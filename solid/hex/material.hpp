#pragma once
/// @file material.hpp
/// Hyperelastic laws for the Total Lagrangian hex8 element, written in terms of the
/// Green-Lagrange strain E = (C - I)/2, C = F^T F, and the 2nd Piola-Kirchhoff stress S = dpsi/dE.
///
/// Voigt order (as in Bathe 1996, sec. 6.3.2, matrix B_L): [xx, yy, zz, xy, yz, zx]; strains carry
/// engineering shears (2 E_xy, ...), stresses the tensor components (S_xy, ...), so that
/// S_voigt . dE_voigt = S : dE and D = dS_voigt / dE_voigt is symmetric.
#include <Eigen/Core>

namespace tetfsi::solid::hex {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

enum class MaterialLaw {
  /// St. Venant-Kirchhoff: psi = lambda/2 tr(E)^2 + mu E:E, S = lambda tr(E) I + 2 mu E,
  /// D constant (the linear-elastic matrix of the seed's K_L).
  StVenantKirchhoff,
  /// Compressible neo-Hookean (Bonet & Wood, Nonlinear Continuum Mechanics, eq. 6.28):
  /// psi = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2,
  /// S = mu (I - C^-1) + lambda ln J C^-1,
  /// D_IJKL = lambda C^-1_IJ C^-1_KL + (mu - lambda ln J)(C^-1_IK C^-1_JL + C^-1_IL C^-1_JK).
  NeoHookean,
};

struct Material {
  MaterialLaw law = MaterialLaw::StVenantKirchhoff;
  double youngs_modulus = 1e6;  ///< E [Pa]
  double poisson_ratio = 0.3;   ///< nu [-], in (-1, 0.5)
  double density = 1000.0;      ///< rho [kg/m^3] (reference configuration)

  double lame_lambda() const;  ///< lambda = E nu / ((1 + nu)(1 - 2 nu)) [Pa]
  double lame_mu() const;      ///< mu = E / (2 (1 + nu)) [Pa]
  /// Throws std::invalid_argument naming the bad parameter.
  void validate() const;
};

/// Stress, tangent and energy density at a deformation gradient F.
/// @param F       deformation gradient dx/dX [-]
/// @param S       out: 2nd Piola-Kirchhoff stress [Pa]
/// @param D       out (optional): material tangent dS/dE in Voigt form [Pa]
/// @param psi     out (optional): strain energy density per reference volume [J/m^3]
/// @return false if det F <= 0 (inverted material point): neither law is then admissible
bool evaluate_material(const Material& m, const Eigen::Matrix3d& F, Eigen::Matrix3d& S, Matrix6d* D,
                       double* psi);

/// Voigt index pairs [xx, yy, zz, xy, yz, zx].
inline constexpr int kVoigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};

/// Cauchy stress sigma = F S F^T / det F [Pa].
Eigen::Matrix3d cauchy_stress(const Eigen::Matrix3d& F, const Eigen::Matrix3d& S);

}  // namespace tetfsi::solid::hex
