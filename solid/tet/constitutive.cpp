#include "solid/tet/constitutive.hpp"

#include <Eigen/LU>

#include "solid/solid_error.hpp"

namespace tetfsi::solid {

void TetMaterial::validate() const {
  if (!(youngs_modulus > 0)) throw SolidError("material: youngs_modulus must be > 0 [Pa]");
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    throw SolidError("material: poisson_ratio must lie in (-1, 0.5)");
  if (!(density > 0)) throw SolidError("material: density must be > 0 [kg/m^3]");
  if (!(rayleigh_alpha >= 0) || !(rayleigh_beta >= 0))
    throw SolidError("material: rayleigh_alpha and rayleigh_beta must be >= 0");
}

Eigen::Matrix3d cauchy_stress(const ConstitutiveParams& p, const Eigen::Matrix3d& F) {
  const double J = F.determinant();
  if (!law_defined_at(p.law, J)) return Eigen::Matrix3d::Zero();
  const Eigen::Matrix3d PFt = first_piola(p, F) * F.transpose();
  return J > 0 ? Eigen::Matrix3d(PFt / J) : PFt;
}

}  // namespace tetfsi::solid
