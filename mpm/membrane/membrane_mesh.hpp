#pragma once
/// @file membrane_mesh.hpp
/// Structured quad meshes for membranes (tests, benchmarks and the paper's examples).
#include <Eigen/Core>

#include <array>
#include <vector>

namespace tetfsi::mpm {

struct QuadMesh {
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<int, 4>> quads;  ///< counter-clockwise about the normal
};

/// nu x nv quads on the parallelogram origin + s u + t v, s, t in [0, 1]; normal along u x v.
QuadMesh rectangle_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                        int nu, int nv);

/// An open polyline in the x-y plane extruded along z from z0 to z1 with nz layers. For a polyline
/// running counter-clockwise around a region, the quad normals (tangent x e_z) point outwards.
QuadMesh extruded_polyline(const std::vector<Eigen::Vector2d>& points, double z0, double z1, int nz);

}  // namespace tetfsi::mpm
