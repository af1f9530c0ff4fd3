#pragma once
/// @file features.hpp
/// Sharp edges of a triangle surface, chained into polylines, for CGAL Mesh_3 to keep as features
/// (protected by balls, so box corners and sheet edges stay sharp instead of being rounded).
#include <Eigen/Core>
#include <vector>

#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh {

/// Angle [deg] between the normals of the two triangles at every edge, indexed like the result
/// of mesh_edges(). @pre closed, consistently oriented surface
std::vector<double> edge_normal_angles_deg(const SurfaceMesh& s);

/// Polylines made of the edges whose normal angle exceeds `angle_deg`: chains through vertices
/// with exactly two sharp edges, broken at vertices with another number (corners). A closed loop
/// repeats its first point at the end. Deterministic order (by smallest vertex index).
std::vector<std::vector<Eigen::Vector3d>> sharp_polylines(const SurfaceMesh& s, double angle_deg);

/// True if every edge is either flat (normal angle < flat_deg) or sharp (> sharp_deg): a
/// piecewise-flat, CAD-like surface (boxes, sheets). Scanned or smooth models (the bunny, a sphere)
/// are not, and get no features: protecting their scattered creases only makes slivers.
bool is_piecewise_flat(const SurfaceMesh& s, double flat_deg = 1.0, double sharp_deg = 60.0);

}  // namespace tetfsi::mesh
