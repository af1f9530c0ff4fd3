#pragma once
/// @file solid_geometry.hpp
/// The placed rest surfaces of the scene's solids, from the mesh module's primitives and assimp
/// import (mesh/primitives.hpp, mesh/surface_import.hpp), checked with mesh/surface_checks.hpp,
/// and the placed tet meshes of `volume_mesh` solids (mesh/volume_mesh.hpp).
#include <string>
#include <vector>

#include "apps/scene/scene.hpp"
#include "mesh/surface_import.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::run {

/// The rigid placement of /solids/i (placement.rotation_deg, placement.translation; unit scale 1).
mesh::Placement placement_of(const scene::Json& solid);

/// The placed, checked rest surface of the solid described by resolved JSON `solid` (/solids/i).
/// Surfaces whose normals point inwards are flipped, with a message added to `warnings`.
/// @throws InputError naming the solid (and file) if the surface is unreadable, open,
///         non-manifold or self-intersecting
/// `cavity` (coupled runner only): receives cavity_of(solid); without it a `sphere_shell` is
/// refused (InputError), so that no runner meshes a shell as a full ball by mistake.
/// `volume_tets` (optional) receives the tet count of a `volume_mesh` solid (else it is left alone).
mesh::SurfaceMesh surface_of(const scene::Json& solid, std::vector<std::string>& warnings,
                             mesh::SurfaceMesh* cavity = nullptr, int* volume_tets = nullptr);

/// The placed, checked tet mesh of a `volume_mesh` solid (/solids/i, geometry type
/// "volume_mesh"): the file's tets (mesh::import_volume_mesh: checked, unused nodes dropped,
/// orientation made positive) scaled by geometry.unit_scale, rotated by placement.rotation_deg,
/// translated by placement.translation. surface_of gives its boundary surface.
/// @throws InputError naming the solid and the file
mesh::TetMesh volume_mesh_of(const scene::Json& solid, std::vector<std::string>& warnings);

/// The placed cavity surface of a `sphere_shell` solid (a sphere of radius - thickness, outward),
/// or an empty surface for every other geometry. surface_of gives the shell's outer surface.
/// @throws InputError naming the solid
mesh::SurfaceMesh cavity_of(const scene::Json& solid);

/// The closed surface file of `placed` (its keys file, unit_scale, rotation_deg, translation: a
/// `mesh` liquid region or container), scaled, rotated, translated and checked; `what` names it in
/// messages. @throws InputError naming the file if it is unreadable, open, non-manifold or
/// self-intersecting
mesh::SurfaceMesh placed_surface_file(const scene::Json& placed, const std::string& what,
                                      std::vector<std::string>& warnings);

/// The placed, checked surface of a `mesh` liquid region (/fluid/regions/i with type "mesh"):
/// the file scaled by unit_scale, rotated by rotation_deg, translated by translation.
/// @throws InputError naming the file if it is unreadable, open, non-manifold or self-intersecting
mesh::SurfaceMesh liquid_region_surface(const scene::Json& region, std::vector<std::string>& warnings);

/// Imports and checks one surface file for `tetfsi mesh`.
/// @throws InputError as surface_of
mesh::SurfaceMesh import_checked(const std::string& file, double unit_scale, std::vector<std::string>& warnings);

}  // namespace tetfsi::run
