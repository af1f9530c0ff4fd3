#pragma once
/// @file solid_fixtures.hpp
/// Small shared inputs of the solid tests.
#include "mesh/tet_mesh.hpp"
#include "solid/tet/material.hpp"

namespace tetfsi::test {

/// The unit right tet (0,0,0), (1,0,0), (0,1,0), (0,0,1), positively oriented [m].
inline mesh::TetMesh unit_tet() {
  mesh::TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  return m;
}

/// A material with the given law and Young's modulus [Pa], nu = 0.3, rho = 1000 kg/m^3.
inline solid::TetMaterial tet_material(solid::ConstitutiveLaw law, double youngs_modulus) {
  solid::TetMaterial mat;
  mat.youngs_modulus = youngs_modulus;
  mat.poisson_ratio = 0.3;
  mat.density = 1000;
  mat.law = law;
  return mat;
}

}  // namespace tetfsi::test
