#pragma once
/// @file tet_mesh_state.hpp
/// A TetMesh in a checkpoint (support/binary_stream.hpp): vertices, tets and labels, bit for bit.
#include "mesh/submesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

template <class Archive>
void serialize(Archive& a, TetMesh& m) {
  a(m.vertices, m.tets, m.subdomain);
}

/// The parent maps of a Submesh (its own mesh is rebuilt by the set-up and does not change).
template <class Archive>
void serialize_maps(Archive& a, Submesh& s) {
  a(s.to_parent_vertex, s.from_parent_vertex, s.to_parent_tet);
}

}  // namespace tetfsi::mesh
