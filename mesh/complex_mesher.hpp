#pragma once
/// @file complex_mesher.hpp
/// Tetrahedral meshing with CGAL Mesh_3 behind plain arrays (no CGAL type crosses this header).
///
/// build_complex() meshes a fluid box with every solid inside it as ONE complex
/// (CGAL Polyhedral_complex_mesh_domain_3): fluid is subdomain kFluidSubdomain, solid i is
/// solid_subdomain(i). Every interface triangle is therefore shared by exactly one fluid tet and
/// one solid tet, and each solid's FEM mesh is its own subdomain's tets.
/// CGAL resamples the input surfaces: the interface approximates the input (about 1e-3 of its
/// size at 100k tets); it does not keep the input triangles.
#include <Eigen/Core>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/surface_mesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

/// Thrown for invalid geometry input (open, non-manifold, self-intersecting surfaces, solids
/// outside the box, overlapping solids). what() names the input and the defect.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Size controls [m]. The cell size grows linearly with distance from the solids, from
/// `edge_length_near_solids` at their surface to `edge_length` at distance `grading_distance`.
struct MeshSizing {
  double edge_length = 0.1;              ///< target edge length far from solids [m]
  double edge_length_near_solids = 0.0;  ///< target edge length at solid surfaces; 0: = edge_length
  double grading_distance = 0.0;         ///< distance over which the size grades [m]; 0: no grading
  double facet_distance = 0.0;           ///< max surface approximation error [m]; 0: the edge length
                                         ///< at the solids (edge_length_near_solids or edge_length) / 10
  /// Sharp edges of the solids kept as features (corners stay sharp): edges whose facet normals
  /// differ by more than this angle [deg]. < 0 (default): automatic, 60 deg for piecewise-flat
  /// surfaces (boxes, sheets; see is_piecewise_flat in features.hpp), none for smooth or scanned
  /// models (protecting a scan's scattered creases only makes slivers). 0: none. The box edges of
  /// build_complex are always kept.
  double solid_feature_angle_deg = -1.0;
  /// A further size bound [m] at each point (e.g. finer near a liquid's surface): the size used
  /// is the smaller of this and the graded size above. Empty: none.
  std::function<double(const Eigen::Vector3d&)> size_at;
};

/// Meshes the box [lo, hi] filled with fluid and containing the given closed, outward-oriented,
/// pairwise disjoint solid surfaces.
/// @throws MeshError if a solid is not strictly inside the box, meshing loses a subdomain, or a
/// solid's tets hold a volume more than 25% away from what its surface encloses (a solid thinner
/// than the tets near it, collapsed into slivers)
TetMesh build_complex(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing);

/// As above, with cavities: `cavities[i]` (a closed, outward-oriented surface strictly inside
/// solids[i], or an empty surface for none) is cut out of solid i and filled with fluid, so the
/// solid is a shell and its cavity is fluid (label kFluidSubdomain, the same label as the fluid
/// outside: one fluid, two disconnected regions). The cavity surface is an interface like the
/// outer one: every cavity triangle is shared by one fluid and one solid tet. Grading runs from
/// both surfaces. `cavities` is empty or has one entry per solid.
/// Patches: outer (solid i, fluid), cavity (fluid, solid i) as (inside, outside).
/// @throws MeshError as above, or if a cavity is open, self-intersecting or not strictly inside
TetMesh build_complex(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing,
                      const std::vector<SurfaceMesh>& cavities);

/// As above, with the fluid container any closed surface instead of a box (a sphere, a cylinder:
/// make_sphere, make_cylinder in primitives.hpp): `container` (closed, outward-oriented, without
/// self-intersections) bounds the fluid; every solid must lie strictly inside it. Its sharp edges
/// (facet normals differing by > 60 deg, e.g. a cylinder's rims) are kept as features. Patch of the
/// container: (fluid, outside) = (kFluidSubdomain, 0).
/// @throws MeshError if the container is not a valid closed surface, a solid is not strictly inside
/// it, or as above
TetMesh build_complex(const SurfaceMesh& container, const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing,
                      const std::vector<SurfaceMesh>& cavities);

/// A liquid-filled shell with nothing outside (the filled toy): the region between the closed
/// outward surfaces `outer` and `cavity` (strictly inside outer) is solid_subdomain(0), the inside
/// of `cavity` is fluid (kFluidSubdomain). No box: the outer surface is the mesh's boundary, the
/// fluid's only boundary is the cavity interface (a closed region, Chentanez 2006 §3.4). Sizing as
/// in build_complex, with grading from both surfaces.
/// @throws MeshError on bad surfaces, a cavity not strictly inside, or a lost subdomain
TetMesh mesh_filled_shell(const SurfaceMesh& outer, const SurfaceMesh& cavity, const MeshSizing& sizing);

/// Meshes the inside of one closed, outward-oriented surface alone (solid-only scenes build no
/// fluid mesh). All tets get `subdomain`. Uses sizing.edge_length everywhere (no grading); the
/// facet distance defaults as in build_complex.
TetMesh mesh_solid(const SurfaceMesh& surface, const MeshSizing& sizing, int subdomain = solid_subdomain(0));

}  // namespace tetfsi::mesh
