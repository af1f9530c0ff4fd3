#pragma once
/// @file constitutive.hpp
/// The tet element's view of the hyperelastic laws (solid/laws/hyperelastic_law.hpp): energy density
/// Psi(F), first Piola-Kirchhoff stress P = dPsi/dF, its differential and its exact 9 x 9 tangent
/// dP/dF (energy_density, first_piola, first_piola_differential, first_piola_tangent, taking these
/// parameters), evaluated at the constant F of each tet. Per unit reference volume.
#include <Eigen/Core>

#include "solid/laws/hyperelastic_law.hpp"
#include "solid/tet/material.hpp"

namespace tetfsi::solid {

/// Lame parameters and law, precomputed from a TetMaterial.
struct ConstitutiveParams : HyperelasticParams {
  static ConstitutiveParams from(const TetMaterial& m) {
    ConstitutiveParams p;
    p.law = m.law;
    p.lambda = m.lambda();
    p.mu = m.mu();
    return p;
  }
};

/// Cauchy stress sigma = P F^T / J [Pa] for output (requires J > 0; returns P F^T otherwise).
Eigen::Matrix3d cauchy_stress(const ConstitutiveParams& p, const Eigen::Matrix3d& F);

}  // namespace tetfsi::solid
