#pragma once
/// @file extract_subdomain.hpp
/// The FEM mesh of one solid is its subdomain's tets in the shared fluid+solid mesh
/// (shared/design.md). This extracts them with compact vertex numbering and the map back to
/// the shared mesh's vertices, which the coupling needs to match interface nodes.
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::solid {

struct SubdomainMesh {
  mesh::TetMesh mesh;                 ///< tets of the subdomain, vertices renumbered 0..n-1
  std::vector<int> global_vertex;     ///< local vertex -> vertex of the source mesh
  std::vector<int> global_tet;        ///< local tet -> tet of the source mesh
};

/// @param source     mesh with per-tet labels (empty labels: every tet matches)
/// @param subdomain  label to extract, e.g. mesh::solid_subdomain(0)
/// @throws SolidError if no tet carries the label
SubdomainMesh extract_subdomain(const mesh::TetMesh& source, int subdomain);

}  // namespace tetfsi::solid
