#pragma once
// The 3D patch-test mesh of MacNeal & Harder 1985 (Finite Elements in Analysis and Design 1,
// "A proposed standard set of problems to test finite element accuracy", fig. 3): the unit cube
// split into 7 irregular hexes, an inner hex on 8 interior nodes and one hex between each of its
// faces and the cube's. Nodes 0-7: the cube's corners in VTK order; nodes 8-15: the interior
// nodes, node 8 + i facing corner i.
#include <array>

#include "mesh/hex_mesh.hpp"

namespace tetfsi::test {

inline mesh::HexMesh macneal_harder_mesh() {
  mesh::HexMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1},
                {0.249, 0.342, 0.192}, {0.826, 0.288, 0.288}, {0.850, 0.649, 0.263}, {0.273, 0.750, 0.230},
                {0.320, 0.186, 0.643}, {0.677, 0.305, 0.683}, {0.788, 0.693, 0.644}, {0.165, 0.745, 0.702}};
  m.hexes.push_back({8, 9, 10, 11, 12, 13, 14, 15});
  // Each outer face (outward-normal order of mesh::kHexFaces) as the bottom of a hex whose top is
  // the matching inner face: bottom counter-clockwise seen from the top means reversing the order.
  for (const auto& f : mesh::kHexFaces)
    m.hexes.push_back({f[3], f[2], f[1], f[0], 8 + f[3], 8 + f[2], 8 + f[1], 8 + f[0]});
  return m;
}

}  // namespace tetfsi::test
