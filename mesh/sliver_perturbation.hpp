#pragma once
/// @file sliver_perturbation.hpp
/// A sliver pass after a remesh (no CGAL): free fluid vertices of tets whose smallest dihedral
/// angle is below a threshold are moved to the best of a few candidate positions, kept only if the
/// smallest dihedral angle over the vertex's star increases and no tet flattens. Candidates: toward
/// the centroid of the vertex's neighbours (Laplacian smoothing), and along the normal of the
/// sliver's face opposite the vertex, both ways (the move that opens a sliver, as in the
/// perturbation of Tournois, Srinivasan & Alliez 2009, "Perturbing slivers in 3D Delaunay meshes",
/// here without its gradient: a fixed set of step lengths).
///
/// Written by hand: CGAL's perturb_mesh_3 / exude_mesh_3 need a Mesh_3 domain and complex, which
/// a remeshed tet soup no longer has. Vertices of solid tets and of the box boundary never move,
/// so the interface and the solids stay identical.
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

struct SliverPassReport {
  int slivers_before = 0;   ///< fluid tets below the threshold before the pass
  int slivers_after = 0;    ///< and after (among the tets around the slivers' vertices)
  int moved_vertices = 0;
};

/// Moves free fluid vertices of `mesh` in place (see the file comment), `sweeps` times over the
/// tets below `threshold_deg`.
SliverPassReport perturb_slivers(TetMesh& mesh, double threshold_deg, int sweeps = 3);

}  // namespace tetfsi::mesh
