#pragma once
/// @file container.hpp
/// The fluid's container from /domain: the domain box, or the sphere or cylinder of
/// /domain/container (docs/scene_format.md). Shared by the runners that mesh a fluid and by the
/// preflight checks, so `validate` and `run` see the same container.
#include <vector>

#include "apps/scene/scene.hpp"
#include "mesh/complex_mesher.hpp"
#include "solid/contact/static_obstacles.hpp"

namespace tetfsi::run {

/// The closed, outward surface of /domain/container placed in the scene: an icosphere
/// (mesh::make_sphere) or a prism over a regular polygon (mesh::make_cylinder, its axis turned to
/// x, y or z by a cyclic permutation of the coordinates). Empty when the container is the box.
mesh::SurfaceMesh container_surface(const scene::Json& domain);

/// mesh::build_complex of the scene's container (the box [/domain/lo, /domain/hi] or the
/// container surface) with the solids and their cavities (empty or one per solid).
/// @throws mesh::MeshError as build_complex
mesh::TetMesh mesh_container(const scene::Json& domain, const std::vector<mesh::SurfaceMesh>& solids,
                             const mesh::MeshSizing& sizing, const std::vector<mesh::SurfaceMesh>& cavities = {});

/// The container's walls as contact planes for the solids (/coupling/wall_contact), each set back
/// into the fluid by `gap` [m]: the box's six faces, or one plane per face of the (convex) sphere or
/// cylinder surface, coplanar faces merged. The inside of the container less the gap is where
/// every plane's φ(x) = (x − point)·n is positive.
std::vector<solid::PlaneObstacle> container_wall_planes(const scene::Json& domain, double gap);

}  // namespace tetfsi::run
