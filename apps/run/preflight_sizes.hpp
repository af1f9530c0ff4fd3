#pragma once
/// @file preflight_sizes.hpp
/// Tet estimates of the size keys that refine a mesh locally (preflight.cpp's estimate_tets):
/// fluid.surface_edge_length (a band around a liquid's free surface, surface_refinement.hpp) and
/// mesh.facet_distance (surface facets on curved solids). Each count uses the density of a CGAL
/// Mesh_3 mesh, 6 sqrt(2) / h^3 tets per unit volume at edge length h (a regular tet of edge h has
/// volume h^3 / (6 sqrt 2)).
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// Area [m^2] of the initial free surface of a liquid with `fluid.fill` "regions": per region, a
/// box's faces inside the domain and off its walls (faces on a wall are walls), a sphere's
/// 4 pi r^2 (plus pi r^2 for a cap), "below"'s cut of the domain box (bounded by its shadow
/// sum_k |up_k| A_k, A_k the box's face area normal to axis k), and a "mesh" region's surface
/// area, given in `mesh_areas` in the order of the mesh regions. Overlaps are not subtracted (an
/// upper bound).
double free_surface_area(const scene::Json& js, const std::vector<double>& mesh_areas);

/// Tets in the refined band of surface_refinement.hpp around a free surface of area A, both sides:
///   N = 6 sqrt(2) 2 A int_0^inf (h(d)^-3 - h_far^-3) dd
///     = 6 sqrt(2) 2 A [3 (h_s^-2 - h_s h_far^-3) + G / (2 (h_far - h_s)) (h_s^-2 - h_far^-2) - G / h_far^3],
/// h(d) = h_s for d < 3 h_s, then linear to h_far over G = max(grading_distance, 3 h_s) (the
/// volume beyond is counted at h_far with the domain). 0 when h_s >= h_far.
double surface_band_tets(double area, double surface_edge, double far_edge, double grading);

/// Edge length [m] of the surface facets of a solid of mean curvature radius R under
/// mesh.facet_distance delta: a facet of circumradius rho on a sphere of radius R lies rho^2 / (2R)
/// from it, so delta bounds rho by sqrt(2 R delta) and the edge (sqrt 3 rho) by sqrt(6 R delta);
/// the smaller of that and `edge`. R = 3 V / A (exact for a sphere; a / 2 for a cube, whose
/// sharp edges the mesher protects, so there an upper bound on the count). `edge` when delta is 0
/// (the default, edge / 10, which refines only solids thinner than 1.7 edges, already meshed at
/// their thickness).
double facet_edge(double edge, double facet_distance, double curvature_radius);

}  // namespace tetfsi::run
