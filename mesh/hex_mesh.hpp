#pragma once
/// @file hex_mesh.hpp
/// Plain-array 8-node hexahedral mesh (Total Lagrangian solids).
/// Node order is VTK_HEXAHEDRON's: bottom face (0,1,2,3) counter-clockwise seen from above
/// (+z), then the top face (4,5,6,7) above nodes 0..3.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace tetfsi::mesh {

struct HexMesh {
  std::vector<Eigen::Vector3d> vertices;   ///< #V reference positions [m]
  std::vector<std::array<int, 8>> hexes;   ///< #H vertex indices, VTK order

  int num_vertices() const { return static_cast<int>(vertices.size()); }
  int num_hexes() const { return static_cast<int>(hexes.size()); }
};

}  // namespace tetfsi::mesh
