#pragma once
/// @file container.hpp
/// The fluid's container from /domain: the domain box, or the sphere or cylinder of
/// /domain/container (docs/scene_format.md). Shared by the runners that mesh a fluid and by the
/// preflight checks, so `validate` and `run` see the same container.
#include <string>
#include <vector>

#include "apps/run/errors.hpp"
#include "apps/scene/scene.hpp"
#include "mesh/complex_mesher.hpp"
#include "solid/contact/static_obstacles.hpp"

namespace tetfsi::run {

/// The closed, outward surface of /domain/container placed in the scene: an icosphere
/// (mesh::make_sphere), a prism over a regular polygon (mesh::make_cylinder, its axis turned to
/// x, y or z by a cyclic permutation of the coordinates) or the placed surface file (`mesh`).
/// Empty when the container is the box. @throws InputError for a `mesh` file that is unreadable,
/// open, non-manifold or self-intersecting
mesh::SurfaceMesh container_surface(const scene::Json& domain);

/// The InputError of a failed meshing, "meshing failed: ...", with mesh::build_complex's solid
/// indices ("solid 2") named as the scene names them ("solid 'flag' (/solids/2)"); `names` are
/// the /solids names in order.
InputError meshing_failure(const mesh::MeshError& error, const std::vector<std::string>& names);

/// mesh::build_complex of the scene's container (the box [/domain/lo, /domain/hi] or the
/// container surface) with the solids and their cavities (empty or one per solid).
/// @throws mesh::MeshError as build_complex
mesh::TetMesh mesh_container(const scene::Json& domain, const std::vector<mesh::SurfaceMesh>& solids,
                             const mesh::MeshSizing& sizing, const std::vector<mesh::SurfaceMesh>& cavities = {});

/// The container's walls as contact obstacles for the solids (/coupling/wall_contact), each set
/// back into the fluid by `gap` [m]: the box's six faces; for a sphere container the inside of the
/// sphere inscribed in its icosphere (radius: the nearest face plane's distance from the centre);
/// for a cylinder the inside of the cylinder inscribed in its prism (R cos(π/segments)) and its
/// two end planes; for a `mesh` container the inside of its surface file set back by `gap`
/// (signed distance to the file's triangles, solid::ImplicitObstacle). The inscribed smooth shapes keep every solid node inside the polyhedron the
/// fluid is meshed in, and give one normal per node (a node against a planes-per-face wall can
/// hop between faces from one contact round to the next).
struct ContainerWalls {
  std::vector<solid::PlaneObstacle> planes;
  std::vector<solid::SphereInteriorObstacle> spheres;
  std::vector<solid::CylinderInteriorObstacle> cylinders;
  std::vector<solid::ImplicitObstacle> implicits;
  void add_to(solid::StaticObstacles& obstacles) const;
  std::size_t count() const { return planes.size() + spheres.size() + cylinders.size() + implicits.size(); }
};
ContainerWalls container_walls(const scene::Json& domain, double gap);

}  // namespace tetfsi::run
