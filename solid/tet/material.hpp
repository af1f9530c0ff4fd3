#pragma once
/// @file material.hpp
/// Material parameters of a tetrahedral FEM body (keys of the scene's /solids/i/material in brackets).

namespace tetfsi::solid {

/// Constitutive law of a tet element.
enum class ConstitutiveLaw {
  /// St. Venant-Kirchhoff: Green strain E = (F^T F - I)/2, S = lambda tr(E) I + 2 mu E
  /// (O'Brien & Hodgins 1999; Chentanez et al. 2006 sec. 3.2). Collapses under strong
  /// compression; inverted elements stop the run with an error.
  kStVK,
  /// Compressible "stable" neo-Hookean (Smith, de Goes & Kim 2018, without the log term):
  /// Psi = mu/2 (tr(F^T F) - 3) + lambda'/2 (J - a)^2, lambda' = lambda + mu, a = 1 + mu/lambda'.
  /// Defined and smooth through J = det F <= 0, so inverted elements are pushed back: the
  /// inversion-robust option. Same small-strain Lame parameters as kStVK.
  kStableNeoHookean,
};

struct TetMaterial {
  double youngs_modulus = 1e6;  ///< E [Pa] ("youngs_modulus")
  double poisson_ratio = 0.3;   ///< nu, in (-1, 0.5) ("poissons_ratio")
  double density = 1000.0;      ///< rho [kg/m^3] ("density")
  double rayleigh_alpha = 0.0;  ///< mass-proportional damping alpha [1/s] ("rayleigh_alpha")
  double rayleigh_beta = 0.0;   ///< stiffness-proportional damping beta [s] ("rayleigh_beta")
  ConstitutiveLaw law = ConstitutiveLaw::kStVK;  ///< ("constitutive": "stvk" or "neohookean")

  /// Lame parameters: lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)) [Pa].
  double lambda() const {
    return youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  }
  double mu() const { return youngs_modulus / (2 * (1 + poisson_ratio)); }

  /// @throws SolidError naming the offending parameter
  void validate() const;
};

}  // namespace tetfsi::solid
