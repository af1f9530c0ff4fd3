#pragma once
/// @file hex_volume_mesh.hpp
/// Hexahedral meshes read from files (VTK .vtu with VTK_HEXAHEDRON cells, Gmsh .msh with 8-node
/// hexahedra) for hex8 solids whose mesh the user brings, checked before they reach the Total
/// Lagrangian model (solid/hex/hex_model.hpp). The counterpart of volume_mesh.hpp for tets.
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "mesh/surface_import.hpp"

namespace tetfsi::mesh {

/// Relative corner Jacobian at or below which a hex corner counts as degenerate:
/// det[x_a - x_i, x_b - x_i, x_c - x_i] <= kDegenerateHexCorner * l^3, l the hex's longest edge
/// (a cube has det = l^3 at every corner).
constexpr double kDegenerateHexCorner = 1e-12;

/// Reads the hexes of `path` by its extension: `.vtu` (io::read_vtu; every cell must be
/// VTK_HEXAHEDRON, type 12) or `.msh` (io::read_msh_hexes, Gmsh type 5). No placement, no checks.
/// @throws MeshError naming the file and the cause (missing, over kMaxSurfaceBytes, unreadable,
///         another cell type with its index and type, unknown extension)
HexMesh read_hex_volume_mesh(const std::string& path);

/// Checks a hex mesh for use as a hex8 solid and makes it tidy. Every corner i of every hex has the
/// Jacobian sign J_i = det[x_a - x_i, x_b - x_i, x_c - x_i] of the trilinear map (a, b, c its
/// edge neighbours, kHexCornerNeighbours). Refused (MeshError starting with `label` and naming the
/// hex): no hexes; a non-finite coordinate; a hex repeating a node; a degenerate corner
/// (|J_i| <= kDegenerateHexCorner l^3); a hex with corners of both signs (inverted or folded: the
/// first bad corner and its node are named); hexes of both orientations (a tangled mesh, or hexes
/// numbered mirror-wise among the others); two used nodes at the same position (duplicate nodes:
/// the hexes on either side would not be joined); a face shared by more than two hexes; hexes
/// that fall apart into more than one face-connected piece. Repaired, with a message in
/// `warnings`: every hex negative at all 8 corners (a file written with the mirrored numbering) is
/// reordered (bottom and top faces swapped); nodes used by no hex are dropped and the rest
/// renumbered in order.
void check_hex_volume_mesh(HexMesh& mesh, const std::string& label, std::vector<std::string>& warnings);

/// read_hex_volume_mesh, placement (x -> R (unit_scale x) + translation, orientation kept) and
/// check_hex_volume_mesh with the file as the label.
/// @throws MeshError as above
HexMesh import_hex_volume_mesh(const std::string& path, const Placement& placement,
                               std::vector<std::string>& warnings);

}  // namespace tetfsi::mesh
