#pragma once
/// @file hex_test_states.hpp
/// Random element geometries and deformed states shared by the hex8 element tests.
#include <random>

#include "solid/hex/hex8_element.hpp"

namespace tetfsi::solid::hex::testing {

/// A distorted unit-ish hexahedron: corners of [0, 1]^3 moved by up to +-0.15 (det J > 0 everywhere).
inline Matrix83d distorted_hex(std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  Matrix83d X;
  for (int a = 0; a < 8; ++a)
    for (int k = 0; k < 3; ++k) X(a, k) = 0.5 * (kHexCorners[a][k] + 1.0) + jitter(rng);
  return X;
}

/// A finite homogeneous stretch/shear plus nodal noise of up to 0.1 (an enhanced element's modes
/// are then non-zero).
inline Matrix83d random_displacement(std::mt19937& rng, const Matrix83d& X) {
  std::uniform_real_distribution<double> d(-0.1, 0.1);
  Eigen::Matrix3d A;
  for (int i = 0; i < 9; ++i) A(i) = 2.0 * d(rng);
  Matrix83d u = X * A.transpose();
  for (int i = 0; i < 24; ++i) u(i) += d(rng);
  return u;
}

}  // namespace tetfsi::solid::hex::testing
