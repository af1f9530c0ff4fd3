#pragma once
/// @file scene_values.hpp
/// Values the runners read from the resolved scene, in one place: vectors, mesh sizes and
/// prescribed (kinematic) motion.
#include <Eigen/Core>
#include <array>

#include "apps/scene/scene.hpp"
#include "mesh/complex_mesher.hpp"

namespace tetfsi::run {

/// A 3-vector [x, y, z] of the resolved scene.
Eigen::Vector3d vec3(const scene::Json& j);

/// The held components of a resolved /solids/i/fixed_regions/j: (x, y, z) flags from its
/// `components` array (["x", "y", "z"] by default).
std::array<bool, 3> fixed_components(const scene::Json& fixed_region);

/// Mesh size controls of the resolved /mesh block (apps/scene/blocks/domain.cpp).
mesh::MeshSizing mesh_sizing(const scene::Json& mesh_block);

/// Position at time t [s] of the point with rest position x0 under a resolved /solids/i/motion:
/// constant velocity, constant angular velocity about an axis, or keyframes interpolated
/// linearly (translation and Euler angles) and held beyond the ends. `none`: x0.
Eigen::Vector3d moved(const scene::Json& motion, const Eigen::Vector3d& x0, double t);

}  // namespace tetfsi::run
