#pragma once
/// @file incidence.hpp
/// Vertex-to-element incidence in compressed rows: the elements around each vertex, in element
/// order (a counting sort), with the vertex's place in each element.
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

struct VertexIncidence {
  std::vector<int> start;    ///< num_vertices + 1 offsets into element / local
  std::vector<int> element;  ///< elements around vertex v: element[start[v]] ... element[start[v + 1] - 1]
  std::vector<int> local;    ///< the vertex's index (0 .. nodes_per_element - 1) in each of them
};

/// Incidence of num_vertices vertices in the elements of a flat connectivity array
/// (nodes_per_element ids per element, every id in [0, num_vertices)).
VertexIncidence vertex_incidence(int num_vertices, int nodes_per_element, const std::vector<int>& elements);
/// The tets around each vertex of a tet mesh.
VertexIncidence vertex_incidence(const TetMesh& mesh);

}  // namespace tetfsi::mesh
