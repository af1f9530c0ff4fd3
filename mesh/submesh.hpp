#pragma once
/// @file submesh.hpp
/// Extraction of one subdomain of a TetMesh as a mesh of its own (a solid's FEM mesh is its
/// subdomain's tets of the shared complex).
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

/// The tets labelled `subdomain`, with their vertices renumbered compactly in increasing order of
/// their index in `mesh`.
struct Submesh {
  TetMesh mesh;                       ///< the extracted tets (labels kept)
  std::vector<int> to_parent_vertex;  ///< submesh vertex -> vertex of the parent mesh
  std::vector<int> from_parent_vertex;///< parent vertex -> submesh vertex, -1 if not in the submesh
  std::vector<int> to_parent_tet;     ///< submesh tet -> tet of the parent mesh
};

/// @throws std::invalid_argument if `mesh` has no tet labelled `subdomain`
Submesh extract_subdomain(const TetMesh& mesh, int subdomain);

}  // namespace tetfsi::mesh
