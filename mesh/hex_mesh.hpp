#pragma once
/// @file hex_mesh.hpp
/// Plain-array 8-node hexahedral mesh (Total Lagrangian solids).
/// Node order is VTK_HEXAHEDRON's: bottom face (0,1,2,3) counter-clockwise seen from above
/// (+z), then the top face (4,5,6,7) above nodes 0..3.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace tetfsi::mesh {

/// Local node indices of the 6 faces of a VTK hexahedron, ordered so that their normals (right-hand
/// rule) point out of the element.
inline constexpr int kHexFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                        {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

/// The three edge neighbours of each corner of a VTK hexahedron, ordered so that
/// det[x_a - x_i, x_b - x_i, x_c - x_i] > 0 at every corner i of a positively oriented element
/// (the sign of the trilinear map's Jacobian at that corner).
inline constexpr int kHexCornerNeighbours[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                                   {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};

struct HexMesh {
  std::vector<Eigen::Vector3d> vertices;   ///< #V reference positions [m]
  std::vector<std::array<int, 8>> hexes;   ///< #H vertex indices, VTK order

  int num_vertices() const { return static_cast<int>(vertices.size()); }
  int num_hexes() const { return static_cast<int>(hexes.size()); }
};

}  // namespace tetfsi::mesh
