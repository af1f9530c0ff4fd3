#pragma once
/// Helpers shared by the fluid tests: structured boxes with jittered interior vertices.
#include <Eigen/Core>
#include <random>

#include "mesh/structured_box.hpp"

namespace tetfsi::fluid::testing {

/// Moves every interior vertex of `base` (a structured box over [lo, hi] with cell size h) by a
/// uniform random offset in [-amplitude h, amplitude h]^3. Boundary vertices stay (the box keeps its
/// shape). amplitude <= 0.1 keeps Kuhn tets positively oriented (min altitude 0.707 h).
inline mesh::TetMesh jittered(const mesh::TetMesh& base, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                              double h, double amplitude, std::mt19937& rng) {
  mesh::TetMesh m = base;
  std::uniform_real_distribution<double> d(-amplitude * h, amplitude * h);
  for (auto& x : m.vertices) {
    const bool boundary = ((x - lo).array().abs() < 1e-9).any() || ((x - hi).array().abs() < 1e-9).any();
    const Eigen::Vector3d off(d(rng), d(rng), d(rng));
    if (!boundary) x += off;
  }
  return m;
}

}  // namespace tetfsi::fluid::testing
