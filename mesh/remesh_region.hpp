#pragma once
/// @file remesh_region.hpp
/// Which tets a band remesh touches and which it hands to CGAL (remesher.hpp; no CGAL here).
///
/// The band: fluid tets with a vertex within `band` of a solid vertex. The region given to CGAL:
/// the band, the tets sharing a vertex with it (so no band tet touches the region's hull), every
/// solid that these reach, whole (so the region is a ball around the solids, not a shell; a solid
/// the region does not reach stays out, so a region far from the solids is one piece), then grown
/// until its hull is a 2-manifold: CGAL's build_triangulation cones the hull to one infinite
/// vertex, which needs every hull edge in exactly two hull triangles and a single fan of hull
/// triangles around every hull vertex. Tets around an offending edge or vertex are added until
/// none is left. A region that then encloses a cavity (tets of the complement cut off from the
/// mesh's hull) gets them too.
#include <functional>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

/// Per vertex: 0 free fluid vertex, 1 vertex of a solid tet, 2 other vertex on the hull of the mesh
/// (the box boundary: a face of a single tet).
std::vector<int> vertex_kinds(const TetMesh& mesh);

/// Per tet: 1 if it is a fluid tet with a vertex within `band` [m] of a seed vertex (all fluid tets
/// if band <= 0). Seeds: the vertices flagged in `seeds`, or every solid vertex if it is empty.
std::vector<char> band_tets(const TetMesh& mesh, double band, const std::vector<char>& seeds = {});

/// A sizing field: target edge length [m] at a point.
using SizeField = std::function<double(const Eigen::Vector3d&)>;

/// Per tet: 1 for a fluid tet with a vertex x where the sizing field moved since the mesh was
/// fitted to it, s_now(x) > ratio s_then(x) or s_now(x) ratio < s_then(x), and for the fluid tets
/// within `rings` vertex rings of one (room for CGAL to grade). Comparing the field with itself
/// rather than with the mesh's edges flags only where it moved: a mesh made by Mesh_3, whose edges
/// run up to 1.6 times its size bound (a circumradius bound), is not flagged where nothing moved.
/// Remeshing only these tets (and the region band_region builds around them) fits the mesh to
/// s_now at a cost that follows the moved part of the field (a liquid surface), not the box.
/// Both fields are called once per fluid vertex, from one thread.
std::vector<char> resized_tets(const TetMesh& mesh, const SizeField& size_then, const SizeField& size_now,
                               double ratio, int rings);

/// True if the tets flagged in `region` form a topological ball: the region's Euler characteristic
/// V - E + F - C is 1 and its hull's V - E + F is 2 (a sphere). Coned to CGAL's infinite vertex a
/// ball gives a triangulated 3-sphere, whose Euler relation V - E + F - C = 0
/// Triangulation_data_structure_3::is_valid checks; a region in two pieces, with a tunnel or
/// with a cavity breaks it (seen in MeshUpdate.RemeshingEveryStepKeepsTheSolidAndItsVertices with
/// CGAL's checks on: the broken triangulation went into the remesher unnoticed in Release).
/// @pre the hull of the region is a 2-manifold (band_regions grows it until it is)
bool region_is_ball(const TetMesh& mesh, const std::vector<char>& region);

/// The regions CGAL gets (see the file comment), one flag per tet each: the vertex-connected
/// pieces of the band's region, each grown to a ball (region_is_ball) on its own, so that surface
/// patches far apart (a refit to a liquid surface in several places) are remeshed as several
/// small triangulations rather than as the whole mesh. No two regions share a vertex. Empty if a
/// piece is not a manifold ball within `max_rounds` growth rounds, or keeps a tunnel that two more
/// rings of tets do not close (then the caller
/// hands CGAL the whole mesh).
std::vector<std::vector<char>> band_regions(const TetMesh& mesh, const std::vector<char>& band, int max_rounds = 8);

}  // namespace tetfsi::mesh
