#pragma once
/// @file tet_tools.hpp
/// Tet-mesh helpers the runners need: extraction of one subdomain, the boundary surface of a tet
/// set, measures of a surface, and the node nearest a point. (Quality figures come from
/// mesh/quality.hpp.)
#include "mesh/surface_mesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::run {

/// The tets with label `subdomain`, with vertices renumbered compactly (subdomain kept); empty if
/// none has it. (mesh::extract_subdomain, which also gives the maps back, throws instead.)
mesh::TetMesh extract_subdomain(const mesh::TetMesh& m, int subdomain);

/// Faces of `m` that belong to one tet only, oriented outward, with vertices renumbered
/// compactly; `to_tet_vertex` (optional) receives, per surface vertex, its vertex in `m`.
mesh::SurfaceMesh boundary_surface(const mesh::TetMesh& m, std::vector<int>* to_tet_vertex = nullptr);

/// Total area of the triangles [m^2].
double surface_area(const mesh::SurfaceMesh& surface);

/// Mean length of the triangles' edges [m] (each edge counted once per triangle); 0 if none.
double mean_edge_length(const mesh::SurfaceMesh& surface);

/// The node whose position in X (3 per node, stacked) is nearest to x (the first of equals; -1 if
/// X holds no node): where a probe or spring given by a point acts on a solid.
int nearest_node(const Eigen::VectorXd& X, const Eigen::Vector3d& x);

}  // namespace tetfsi::run
