#pragma once
/// @file material.hpp
/// Material parameters of a tetrahedral FEM body (keys of the scene's /solids/i/material in brackets).

#include "solid/laws/hyperelastic_law.hpp"

namespace tetfsi::solid {

/// Constitutive law of a tet element: the laws shared by every element (solid/laws/hyperelastic_law.hpp).
/// kStVK collapses under strong compression and stops the run at an inverted element, as do the two
/// laws with ln J or J^{-2/3}; kNeoHookeanStable is smooth through J <= 0 and pushes inverted elements back.
using ConstitutiveLaw = HyperelasticLaw;

struct TetMaterial {
  double youngs_modulus = 1e6;  ///< E [Pa] ("youngs_modulus")
  double poisson_ratio = 0.3;   ///< nu, in (-1, 0.5) ("poissons_ratio")
  double density = 1000.0;      ///< rho [kg/m^3] ("density")
  double rayleigh_alpha = 0.0;  ///< mass-proportional damping alpha [1/s] ("rayleigh_alpha")
  double rayleigh_beta = 0.0;   ///< stiffness-proportional damping beta [s] ("rayleigh_beta")
  ConstitutiveLaw law = ConstitutiveLaw::kStVK;  ///< ("constitutive": a name of parse_hyperelastic_law)

  /// Lame parameters: lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)) [Pa].
  double lambda() const {
    return youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  }
  double mu() const { return youngs_modulus / (2 * (1 + poisson_ratio)); }

  /// @throws SolidError naming the offending parameter
  void validate() const;
};

}  // namespace tetfsi::solid
