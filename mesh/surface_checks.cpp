/// @file surface_checks.cpp
/// Topological checks by hand on plain arrays. CGAL's Polygon_mesh_processing predicates
/// (is_closed, is_non_manifold_vertex, ...) need a halfedge structure, which cannot even be built
/// from a non-manifold or inconsistently oriented soup; these checks must name such defects, so
/// they work on the index triples directly.
#include "mesh/surface_checks.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "support/number_text.hpp"

namespace tetfsi::mesh {
namespace {

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

[[noreturn]] void fail(const std::string& name, const std::string& defect, std::size_t count,
                       const std::string& what, const std::string& example) {
  std::ostringstream msg;
  msg << name << ": " << defect << ": " << count << " " << what << ", e.g. " << example;
  throw MeshError(msg.str());
}

std::string edge_str(int a, int b, int tri) {
  return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ") of triangle " + std::to_string(tri);
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double enclosed_volume(const SurfaceMesh& s) {
  double v = 0.0;
  for (const auto& t : s.triangles)
    v += s.vertices[t[0]].dot(s.vertices[t[1]].cross(s.vertices[t[2]]));
  return v / 6.0;
}

void bounding_box(const SurfaceMesh& s, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = hi = s.vertices.at(0);
  for (const auto& v : s.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

void flip_orientation(SurfaceMesh& s) {
  for (auto& t : s.triangles) std::swap(t[1], t[2]);
}

void check_topology(const SurfaceMesh& s, const std::string& name) {
  if (s.triangles.empty()) throw MeshError(name + ": no triangles");
  const int nv = s.num_vertices();
  for (int f = 0; f < s.num_triangles(); ++f) {
    for (int i : s.triangles[f])
      if (i < 0 || i >= nv)
        fail(name, "vertex index out of range", 1, "triangle", "triangle " + std::to_string(f) + " uses vertex " +
                                                                std::to_string(i) + " of " + std::to_string(nv));
  }
  for (const auto& v : s.vertices)
    if (!v.allFinite()) throw MeshError(name + ": a vertex coordinate is not finite");

  std::size_t degenerate = 0;
  int degenerate_example = -1;
  for (int f = 0; f < s.num_triangles(); ++f) {
    const auto& t = s.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      if (degenerate++ == 0) degenerate_example = f;
    }
  }
  if (degenerate > 0)
    fail(name, "degenerate triangles (a vertex repeated)", degenerate, "triangles",
         "triangle " + std::to_string(degenerate_example));

  // Directed edge count per undirected edge: +1 for a -> b with a < b, and the number of uses.
  struct EdgeUse { int uses = 0; int forward = 0; };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(3 * s.triangles.size());
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      auto& e = edges[edge_key(a, b)];
      ++e.uses;
      if (a < b) ++e.forward;
    }
  // Count each defect once per undirected edge; the example is the first one in triangle order.
  std::size_t open = 0, nonmanifold = 0, flipped = 0;
  std::string open_ex, nonmanifold_ex, flipped_ex;
  for (const auto& [key, e] : edges) {
    open += (e.uses == 1);
    nonmanifold += (e.uses > 2);
    flipped += (e.uses == 2 && e.forward != 1);
  }
  for (int f = 0; f < s.num_triangles() && (open_ex.empty() || nonmanifold_ex.empty() || flipped_ex.empty()); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = s.triangles[f][k], b = s.triangles[f][(k + 1) % 3];
      const auto& e = edges[edge_key(a, b)];
      if (e.uses == 1 && open_ex.empty()) open_ex = edge_str(a, b, f);
      if (e.uses > 2 && nonmanifold_ex.empty())
        nonmanifold_ex = edge_str(a, b, f) + " (in " + std::to_string(e.uses) + " triangles)";
      if (e.uses == 2 && e.forward != 1 && flipped_ex.empty()) flipped_ex = edge_str(a, b, f);
    }
  if (open > 0) fail(name, "not closed", open, "boundary edges (in only one triangle)", open_ex);
  if (nonmanifold > 0) fail(name, "non-manifold", nonmanifold, "edges in more than two triangles", nonmanifold_ex);
  if (flipped > 0)
    fail(name, "inconsistently oriented", flipped, "edges used in the same direction by both triangles", flipped_ex);

  // Vertex-manifold: the triangles around each vertex must form one fan, i.e. be connected
  // through the edges at that vertex (union-find over the incident triangles).
  std::vector<std::vector<int>> around(nv);
  for (int f = 0; f < s.num_triangles(); ++f)
    for (int i : s.triangles[f]) around[i].push_back(f);
  std::size_t bad_vertices = 0;
  int bad_example = -1;
  for (int v = 0; v < nv; ++v) {
    const auto& fan = around[v];
    if (fan.empty()) continue;
    std::vector<int> parent(fan.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::unordered_map<int, int> first_with;  // other vertex w of edge (v, w) -> fan slot
    for (int j = 0; j < static_cast<int>(fan.size()); ++j)
      for (int w : s.triangles[fan[j]]) {
        if (w == v) continue;
        auto [it, inserted] = first_with.emplace(w, j);
        if (!inserted) parent[find_root(parent, j)] = find_root(parent, it->second);
      }
    int roots = 0;
    for (int j = 0; j < static_cast<int>(fan.size()); ++j) roots += (find_root(parent, j) == j);
    if (roots > 1 && bad_vertices++ == 0) bad_example = v;
  }
  if (bad_vertices > 0)
    fail(name, "non-manifold", bad_vertices, "vertices where separate surface sheets touch",
         "vertex " + std::to_string(bad_example));
}

std::vector<std::string> validate_surface(SurfaceMesh& s, const std::string& name) {
  std::vector<std::string> warnings;
  check_topology(s, name);
  // Drop vertices no triangle uses (harmless, but CGAL's builders reject them).
  std::vector<int> remap(s.vertices.size(), -1);
  for (const auto& t : s.triangles)
    for (int i : t) remap[i] = 0;
  const auto unused = static_cast<std::size_t>(std::count(remap.begin(), remap.end(), -1));
  if (unused > 0) {
    std::vector<Eigen::Vector3d> kept;
    for (std::size_t i = 0; i < remap.size(); ++i)
      if (remap[i] == 0) {
        remap[i] = static_cast<int>(kept.size());
        kept.push_back(s.vertices[i]);
      }
    for (auto& t : s.triangles)
      for (int& i : t) i = remap[i];
    s.vertices = std::move(kept);
    warnings.push_back(name + ": removed " + std::to_string(unused) + " vertices not used by any triangle");
  }
  const double volume = enclosed_volume(s);
  Eigen::Vector3d lo, hi;
  bounding_box(s, lo, hi);
  const double scale = (hi - lo).norm();
  if (!(std::abs(volume) > 1e-12 * scale * scale * scale))
    throw MeshError(name + ": encloses zero volume (" + number_text(volume) + " m^3)");
  if (volume < 0.0) {
    flip_orientation(s);
    warnings.push_back(name + ": surface was oriented inward (enclosed volume " + number_text(volume) +
                       " m^3); flipped it to outward");
  }
  const SelfIntersections si = find_self_intersections(s);
  if (si.count > 0)
    fail(name, "self-intersecting", si.count, "intersecting triangle pairs",
         "triangles " + std::to_string(si.example[0]) + " and " + std::to_string(si.example[1]));
  return warnings;
}

}  // namespace tetfsi::mesh
