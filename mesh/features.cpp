/// @file features.cpp
/// Written by hand rather than with CGAL's PMP::detect_sharp_edges so that it stays out of the
/// CGAL translation units (compile cost) and works on the plain arrays directly.
#include "mesh/features.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

namespace tetfsi::mesh {
namespace {

struct Edge {
  int a, b;      // a < b
  int f0, f1;    // the two triangles (f1 = -1 if open)
};

std::vector<Edge> edges_of(const SurfaceMesh& s) {
  std::map<std::pair<int, int>, int> index;
  std::vector<Edge> edges;
  for (int f = 0; f < s.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = std::min(s.triangles[f][k], s.triangles[f][(k + 1) % 3]);
      const int b = std::max(s.triangles[f][k], s.triangles[f][(k + 1) % 3]);
      auto [it, inserted] = index.emplace(std::make_pair(a, b), static_cast<int>(edges.size()));
      if (inserted)
        edges.push_back({a, b, f, -1});
      else
        edges[it->second].f1 = f;
    }
  return edges;
}

Eigen::Vector3d unit_normal(const SurfaceMesh& s, int f) {
  const auto& t = s.triangles[f];
  return (s.vertices[t[1]] - s.vertices[t[0]]).cross(s.vertices[t[2]] - s.vertices[t[0]]).normalized();
}

std::vector<double> angles(const SurfaceMesh& s, const std::vector<Edge>& edges) {
  std::vector<double> out;
  out.reserve(edges.size());
  for (const Edge& e : edges) {
    if (e.f1 < 0) {
      out.push_back(180.0);
      continue;
    }
    const double c = std::clamp(unit_normal(s, e.f0).dot(unit_normal(s, e.f1)), -1.0, 1.0);
    out.push_back(std::acos(c) * 180.0 / M_PI);
  }
  return out;
}

}  // namespace

std::vector<double> edge_normal_angles_deg(const SurfaceMesh& s) { return angles(s, edges_of(s)); }

bool is_piecewise_flat(const SurfaceMesh& s, double flat_deg, double sharp_deg) {
  for (double a : edge_normal_angles_deg(s))
    if (a >= flat_deg && a <= sharp_deg) return false;
  return true;
}

std::vector<std::vector<Eigen::Vector3d>> sharp_polylines(const SurfaceMesh& s, double angle_deg) {
  const std::vector<Edge> edges = edges_of(s);
  const std::vector<double> angle = angles(s, edges);
  std::vector<std::vector<int>> at(s.vertices.size());  // sharp edges at each vertex
  for (int e = 0; e < static_cast<int>(edges.size()); ++e)
    if (angle[e] > angle_deg) {
      at[edges[e].a].push_back(e);
      at[edges[e].b].push_back(e);
    }
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<Eigen::Vector3d>> lines;
  // Walks from vertex v along edge e until a corner (degree != 2) or back to the start.
  auto walk = [&](int v, int e) {
    std::vector<Eigen::Vector3d> line{s.vertices[v]};
    const int start = v;
    while (true) {
      used[e] = 1;
      v = edges[e].a == v ? edges[e].b : edges[e].a;
      line.push_back(s.vertices[v]);
      if (v == start || at[v].size() != 2) break;
      e = at[v][0] == e ? at[v][1] : at[v][0];
      if (used[e]) break;
    }
    lines.push_back(std::move(line));
  };
  for (int v = 0; v < s.num_vertices(); ++v)  // open chains start at corners
    if (at[v].size() != 2)
      for (int e : at[v])
        if (!used[e]) walk(v, e);
  for (int v = 0; v < s.num_vertices(); ++v)  // what is left are closed loops
    for (int e : at[v])
      if (!used[e]) walk(v, e);
  return lines;
}

}  // namespace tetfsi::mesh
