#pragma once
/// @file vtu_tets.hpp
/// A .vtu grid of tetrahedra (as tetfsi writes the fluid and the solids) as a TetMesh, for tests
/// that rebuild a frame's mesh from its file.
#include <cstdint>

#include "mesh/io/vtu_writer.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::test {

/// The grid's points as vertices and each cell's last 4 point indices as a tet (cells are VTK tetra).
inline mesh::TetMesh tet_mesh(const mesh::io::UnstructuredGrid& g) {
  mesh::TetMesh m;
  m.vertices = g.points;
  for (int c = 0; c < g.num_cells(); ++c) {
    const std::int64_t* t = &g.connectivity[g.offsets[c] - 4];
    m.tets.push_back({int(t[0]), int(t[1]), int(t[2]), int(t[3])});
  }
  return m;
}

}  // namespace tetfsi::test
