#pragma once
/// @file tet_tools.hpp
/// Small tet-mesh utilities the runners need for export: quality figures, extraction of one
/// subdomain, and the boundary surface of a tet set.
/// TODO(lead): move to mesh/ (or use the mesh helper's quality report) after the merge.
#include <string>

#include "mesh/surface_mesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::run {

/// Quality of a tet mesh.
struct TetQuality {
  int tets = 0;
  double min_dihedral_deg = 0;   ///< smallest dihedral angle over all tets [deg]
  double max_dihedral_deg = 0;   ///< largest dihedral angle [deg]
  double max_radius_edge = 0;    ///< largest circumradius / shortest edge (regular tet: 0.612)
  double min_volume = 0;         ///< smallest signed volume [m^3] (> 0: no inverted tet)
};
TetQuality tet_quality(const mesh::TetMesh& m);

/// The tets with label `subdomain`, with vertices renumbered compactly (subdomain kept).
mesh::TetMesh extract_subdomain(const mesh::TetMesh& m, int subdomain);

/// Faces of `m` that belong to one tet only, oriented outward.
mesh::SurfaceMesh boundary_surface(const mesh::TetMesh& m);

}  // namespace tetfsi::run
