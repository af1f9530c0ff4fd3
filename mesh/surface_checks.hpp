#pragma once
/// @file surface_checks.hpp
/// Validity checks of closed triangle surfaces before meshing (issue 2, part 4).
///
/// A solid surface must be closed (every edge in exactly two triangles), manifold (edge- and
/// vertex-manifold), consistently oriented, outward (positive enclosed volume) and free of
/// self-intersection. Each failed check throws MeshError naming the input (file or primitive name),
/// the defect, how many elements have it and one example index.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh {

/// Enclosed volume [m^3] by the divergence theorem: V = sum_f (a . (b x c)) / 6 over the triangles
/// (a, b, c). Positive for closed outward surfaces.
double enclosed_volume(const SurfaceMesh& s);

/// Axis-aligned bounding box of the vertices. @pre s has vertices
void bounding_box(const SurfaceMesh& s, Eigen::Vector3d& lo, Eigen::Vector3d& hi);

/// Reverses the orientation of every triangle.
void flip_orientation(SurfaceMesh& s);

/// Checks topology only: indices in range, no degenerate index triple, closed, edge-manifold,
/// vertex-manifold (the triangles around each vertex form one fan), consistently oriented, no
/// unused vertex. @throws MeshError "<name>: <defect>: <count> ..., e.g. <example>"
void check_topology(const SurfaceMesh& s, const std::string& name);

/// Self-intersecting triangle pairs (CGAL Polygon_mesh_processing::self_intersections; triangles
/// sharing a vertex or an edge intersect only if they overlap beyond it).
struct SelfIntersections {
  std::size_t count = 0;             ///< number of intersecting triangle pairs
  std::array<int, 2> example{-1, -1};  ///< one pair of triangle indices (if count > 0)
};
/// @pre check_topology(s) passed
SelfIntersections find_self_intersections(const SurfaceMesh& s);

/// True if the two closed surfaces intersect or one encloses the other
/// (CGAL Polygon_mesh_processing::do_intersect with the bounded-side test).
/// @pre both pass check_topology
bool surfaces_intersect(const SurfaceMesh& a, const SurfaceMesh& b);

/// True if the closed surface `inner` lies strictly inside the closed surface `outer`: no
/// triangles of the two meet (CGAL Polygon_mesh_processing::do_intersect) and a vertex of inner is
/// on outer's bounded side (CGAL::Side_of_triangle_mesh). Used for the cavity of a shell.
/// @pre both pass check_topology, inner has vertices
bool surface_inside(const SurfaceMesh& inner, const SurfaceMesh& outer);

/// Full check of a solid surface: check_topology, then orientation (if the enclosed volume is
/// negative the whole surface is flipped in place and a warning is returned), then
/// self-intersections. @return warnings (empty if none)
/// @throws MeshError on any defect, including zero enclosed volume
std::vector<std::string> validate_surface(SurfaceMesh& s, const std::string& name);

}  // namespace tetfsi::mesh
