/// @file surface_checks_cgal.cpp
/// The one CGAL Polygon_mesh_processing translation unit: self-intersection and surface-surface
/// intersection tests of surface_checks.hpp. Kept apart from surface_checks.cpp so that editing the
/// plain checks does not recompile CGAL.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <iterator>
#include <utility>
#include <vector>

#include "mesh/surface_checks.hpp"

namespace tetfsi::mesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<K::Point_3>;
using Face = CgalMesh::Face_index;

/// Face i of the result is triangle i of `s` (faces are added in order).
CgalMesh to_cgal(const SurfaceMesh& s) {
  CgalMesh m;
  std::vector<CgalMesh::Vertex_index> v;
  v.reserve(s.vertices.size());
  for (const auto& p : s.vertices) v.push_back(m.add_vertex(K::Point_3(p.x(), p.y(), p.z())));
  for (std::size_t f = 0; f < s.triangles.size(); ++f) {
    const auto& t = s.triangles[f];
    if (m.add_face(v[t[0]], v[t[1]], v[t[2]]) == CgalMesh::null_face())
      throw MeshError("surface: CGAL could not add triangle " + std::to_string(f) + " (non-manifold input)");
  }
  return m;
}

}  // namespace

SelfIntersections find_self_intersections(const SurfaceMesh& s) {
  const CgalMesh m = to_cgal(s);
  std::vector<std::pair<Face, Face>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(m, std::back_inserter(pairs));
  SelfIntersections out;
  out.count = pairs.size();
  if (!pairs.empty()) {
    // Smallest pair, so that the example does not depend on the order CGAL reports pairs in.
    std::vector<std::array<int, 2>> sorted;
    for (const auto& [a, b] : pairs) {
      const int i = static_cast<int>(a.idx()), j = static_cast<int>(b.idx());
      sorted.push_back({std::min(i, j), std::max(i, j)});
    }
    out.example = *std::min_element(sorted.begin(), sorted.end());
  }
  return out;
}

bool surfaces_intersect(const SurfaceMesh& a, const SurfaceMesh& b) {
  const CgalMesh ma = to_cgal(a);
  const CgalMesh mb = to_cgal(b);
  return CGAL::Polygon_mesh_processing::do_intersect(
      ma, mb, CGAL::parameters::do_overlap_test_of_bounded_sides(true),
      CGAL::parameters::do_overlap_test_of_bounded_sides(true));
}

bool surface_inside(const SurfaceMesh& inner, const SurfaceMesh& outer) {
  const CgalMesh mi = to_cgal(inner);
  const CgalMesh mo = to_cgal(outer);
  if (CGAL::Polygon_mesh_processing::do_intersect(mi, mo)) return false;  // triangles meet
  // No triangle meets: inner lies wholly on one side of outer, so one vertex decides.
  const CGAL::Side_of_triangle_mesh<CgalMesh, K> side(mo);
  const Eigen::Vector3d& p = inner.vertices.front();
  return side(K::Point_3(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE;
}

}  // namespace tetfsi::mesh
