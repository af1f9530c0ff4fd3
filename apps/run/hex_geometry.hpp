#pragma once
/// @file hex_geometry.hpp
/// The placed hex meshes of hex8 solids (/solids/i with model "hex8"), shared by `validate`
/// (preflight.cpp) and the hex runner (hex_runner.cpp) so that both build the same mesh and give
/// the same verdict: a structured block of a `box` geometry or the hexes of a `volume_mesh` file
/// (mesh/hex_volume_mesh.hpp), then the solid's placement. Boundary-condition and fixed-region
/// boxes are world coordinates: they select nodes of the placed mesh.
#include <string>
#include <vector>

#include "apps/scene/scene.hpp"
#include "mesh/hex_mesh.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::run {

/// The placed, checked hex mesh of a hex8 solid: `box` geometry: nx x ny x nz equal hexes of the
/// box of `size` centred at the origin (solid/hex/block_mesh.hpp); `volume_mesh`: the file's hexes
/// scaled by unit_scale (mesh::import_hex_volume_mesh: checked, unused nodes dropped, orientation
/// made positive); then x -> R x + t with R, t from /placement (rotation keeps every corner
/// Jacobian positive). Warnings (repairs) are added to `warnings`.
/// @throws InputError naming the solid (and file)
mesh::HexMesh hex_mesh_of(const scene::Json& solid, std::vector<std::string>& warnings);

/// The boundary of a hex mesh as triangles (each boundary quad split in two, outward), over all of
/// the mesh's nodes (hex-mesh node indices).
mesh::SurfaceMesh hex_boundary_surface(const mesh::HexMesh& mesh);

/// The regions of a hex8 solid that select nothing on its placed mesh `mesh`, as (JSON pointer,
/// message): a /fixed_regions box or a /boundary_conditions box with no node inside (with the
/// tolerance 1e-9 x the mesh's bounding-box diagonal that solid::hex::make_conditions applies),
/// or a `traction` / `moment_traction` box with no boundary face inside. `ptr` is /solids/i.
std::vector<std::pair<std::string, std::string>> empty_hex_regions(const scene::Json& solid,
                                                                   const mesh::HexMesh& mesh, const std::string& ptr);

}  // namespace tetfsi::run
