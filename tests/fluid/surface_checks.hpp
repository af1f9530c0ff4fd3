#pragma once
/// Test helpers on triangle surfaces (mesh::SurfaceMesh): closedness, enclosed volume, normals and
/// the bending between neighbouring triangles (the render surface's tests).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "mesh/surface_mesh.hpp"

namespace tetfsi::fluid::testing {

/// Volume enclosed by a closed, outward-oriented surface (divergence theorem) [m^3].
inline double enclosed_volume(const mesh::SurfaceMesh& s) {
  double v = 0;
  for (const auto& t : s.triangles) v += s.vertices[t[0]].dot(s.vertices[t[1]].cross(s.vertices[t[2]])) / 6.0;
  return v;
}

/// Directed edges not matched by exactly one opposite edge: 0 for a closed, consistently
/// oriented 2-manifold.
inline int open_or_nonmanifold_edges(const mesh::SurfaceMesh& s) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  int bad = 0;
  for (const auto& [e, n] : directed) {
    const auto it = directed.find({e.second, e.first});
    if (n != 1 || it == directed.end() || it->second != 1) ++bad;
  }
  return bad;
}

inline Eigen::Vector3d area_vector(const mesh::SurfaceMesh& s, const std::array<int, 3>& t) {
  return 0.5 * (s.vertices[t[1]] - s.vertices[t[0]]).cross(s.vertices[t[2]] - s.vertices[t[0]]);
}
inline double area(const mesh::SurfaceMesh& s, const std::array<int, 3>& t) { return area_vector(s, t).norm(); }
inline Eigen::Vector3d normal(const mesh::SurfaceMesh& s, const std::array<int, 3>& t) {
  return area_vector(s, t).normalized();
}

/// The bend across each edge shared by two triangles: the angle between their normals [deg],
/// with the distance between their centroids [m].
struct Bend {
  double angle_deg, distance;
  Eigen::Vector3d where;  ///< midpoint of the shared edge
};
inline std::vector<Bend> bends(const mesh::SurfaceMesh& s) {
  std::map<std::pair<int, int>, std::vector<int>> faces;
  for (int f = 0; f < s.num_triangles(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = s.triangles[f][k], b = s.triangles[f][(k + 1) % 3];
      faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  std::vector<Bend> out;
  for (const auto& [e, fs] : faces) {
    if (fs.size() != 2) continue;
    const auto& p = s.triangles[fs[0]];
    const auto& q = s.triangles[fs[1]];
    const Eigen::Vector3d a = area_vector(s, p), b = area_vector(s, q);
    if (a.norm() == 0 || b.norm() == 0) continue;
    const double c = std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0);
    const Eigen::Vector3d cp = (s.vertices[p[0]] + s.vertices[p[1]] + s.vertices[p[2]]) / 3.0;
    const Eigen::Vector3d cq = (s.vertices[q[0]] + s.vertices[q[1]] + s.vertices[q[2]]) / 3.0;
    out.push_back({std::acos(c) * 180.0 / M_PI, (cp - cq).norm(), 0.5 * (s.vertices[e.first] + s.vertices[e.second])});
  }
  return out;
}

}  // namespace tetfsi::fluid::testing
