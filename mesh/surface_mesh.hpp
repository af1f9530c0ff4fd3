#pragma once
/// @file surface_mesh.hpp
/// Plain-array triangle surface (imported models, primitives, per-frame export).
/// Closed surfaces are oriented with outward normals: (b - a) x (c - a) points out.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace tetfsi::mesh {

struct SurfaceMesh {
  std::vector<Eigen::Vector3d> vertices;       ///< #V positions [m]
  std::vector<std::array<int, 3>> triangles;   ///< #F vertex indices, counter-clockwise from outside

  int num_vertices() const { return static_cast<int>(vertices.size()); }
  int num_triangles() const { return static_cast<int>(triangles.size()); }
};

}  // namespace tetfsi::mesh
