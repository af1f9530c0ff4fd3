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

/// Relative Jacobian at or below which a hex counts as degenerate at a Gauss point:
/// |det(dX/dxi)| <= kDegenerateHexJacobian * (l/2)^3, l the hex's longest edge (a cube of edge l has
/// det(dX/dxi) = (l/2)^3 everywhere).
constexpr double kDegenerateHexJacobian = 1e-12;

/// Reads the hexes of `path` by its extension: `.vtu` (io::read_vtu; every cell must be
/// VTK_HEXAHEDRON, type 12) or `.msh` (io::read_msh_hexes, Gmsh type 5). No placement, no checks.
/// @throws MeshError naming the file and the cause (missing, over kMaxSurfaceBytes, unreadable,
///         another cell type with its index and type, unknown extension)
HexMesh read_hex_volume_mesh(const std::string& path);

/// Checks a hex mesh for use as a hex8 solid and makes it tidy. Every hex is checked where the
/// element integrates, as other finite element codes do: the Jacobian det(dX/dxi) of its trilinear
/// map at the 8 points (+-1/sqrt 3)^3 of the 2 x 2 x 2 Gauss rule (mesh::hex_jacobian_determinant);
/// a corner may be negative (the MacNeal & Harder 1985 patch-test mesh has such corners). Refused
/// (MeshError starting with `label` and naming the hex): no hexes; a non-finite coordinate; a hex
/// repeating a node; a degenerate Gauss point (|det| <= kDegenerateHexJacobian (l/2)^3); a hex
/// with Gauss points of both signs (inverted or folded: the first bad point is named by its index
/// and natural coordinates); hexes of both orientations (a tangled mesh, or hexes numbered
/// mirror-wise among the others); two used nodes at the same position (duplicate nodes: the hexes
/// on either side would not be joined); a face shared by more than two hexes; hexes that fall
/// apart into more than one face-connected piece. Repaired, with a message in `warnings`: every
/// hex negative at all 8 Gauss points (a file written with the mirrored numbering) is reordered
/// (bottom and top faces swapped); nodes used by no hex are dropped and the rest renumbered in
/// order.
void check_hex_volume_mesh(HexMesh& mesh, const std::string& label, std::vector<std::string>& warnings);

/// read_hex_volume_mesh, placement (x -> R (unit_scale x) + translation, orientation kept) and
/// check_hex_volume_mesh with the file as the label.
/// @throws MeshError as above
HexMesh import_hex_volume_mesh(const std::string& path, const Placement& placement,
                               std::vector<std::string>& warnings);

}  // namespace tetfsi::mesh
