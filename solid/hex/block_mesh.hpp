#pragma once
/// @file block_mesh.hpp
/// Structured hexahedral blocks and node/face selections on hex meshes.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "mesh/hex_mesh.hpp"

namespace tetfsi::solid::hex {

/// The box [lo, hi] split into nx x ny x nz equal hexes (VTK_HEXAHEDRON order, positive volume).
/// Node (i, j, k) has index i + (nx + 1) (j + (ny + 1) k).
/// @throws std::invalid_argument if a count is < 1 or hi <= lo in some direction
mesh::HexMesh block_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz);

/// Nodes whose reference position lies in [lo - tol, hi + tol] (componentwise), ascending.
std::vector<int> nodes_in_box(const mesh::HexMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                              double tol = 1e-9);

/// Boundary quads (faces of exactly one hex) whose 4 nodes all lie in the box [lo - tol, hi + tol];
/// each is ordered so that its normal (right-hand rule) points out of the body.
std::vector<std::array<int, 4>> boundary_faces_in_box(const mesh::HexMesh& mesh, const Eigen::Vector3d& lo,
                                                      const Eigen::Vector3d& hi, double tol = 1e-9);

using mesh::kHexFaces;  ///< local node indices of the 6 faces, outward normals (mesh/hex_mesh.hpp)

}  // namespace tetfsi::solid::hex
