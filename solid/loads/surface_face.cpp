#include "solid/loads/surface_face.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace tetfsi::solid {
namespace {

std::vector<FacePoint> triangle_points() {
  std::vector<FacePoint> pts;
  const double st[3][2] = {{0.5, 0.0}, {0.5, 0.5}, {0.0, 0.5}};
  for (const auto& q : st) {
    FacePoint p;
    p.N << 1 - q[0] - q[1], q[0], q[1], 0;
    p.dNds << -1, 1, 0, 0;
    p.dNdt << -1, 0, 1, 0;
    p.weight = 1.0 / 6.0;
    pts.push_back(p);
  }
  return pts;
}

std::vector<FacePoint> quad_points() {
  std::vector<FacePoint> pts;
  const double g = 1.0 / std::sqrt(3.0);
  const double sa[4] = {-1, 1, 1, -1}, ta[4] = {-1, -1, 1, 1};
  for (double s : {-g, g})
    for (double t : {-g, g}) {
      FacePoint p;
      for (int a = 0; a < 4; ++a) {
        p.N(a) = 0.25 * (1 + sa[a] * s) * (1 + ta[a] * t);
        p.dNds(a) = 0.25 * sa[a] * (1 + ta[a] * t);
        p.dNdt(a) = 0.25 * ta[a] * (1 + sa[a] * s);
      }
      p.weight = 1.0;
      pts.push_back(p);
    }
  return pts;
}

bool inside(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double tol) {
  return (p.array() >= lo.array() - tol).all() && (p.array() <= hi.array() + tol).all();
}

}  // namespace

const std::vector<FacePoint>& face_points(const SurfaceFace& face) {
  static const std::vector<FacePoint> tri = triangle_points(), quad = quad_points();
  return face_node_count(face) == 3 ? tri : quad;
}

std::vector<SurfaceFace> tet_boundary_faces(const std::vector<std::array<int, 4>>& tets) {
  // Outward faces of a positive tet (0 1 2 3): the face opposite each vertex.
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, std::pair<int, SurfaceFace>> seen;
  for (const auto& t : tets)
    for (const auto& f : kFaces) {
      const SurfaceFace face{t[f[0]], t[f[1]], t[f[2]], -1};
      std::array<int, 3> key{face[0], face[1], face[2]};
      std::sort(key.begin(), key.end());
      auto [it, added] = seen.emplace(key, std::make_pair(1, face));
      if (!added) ++it->second.first;
    }
  std::vector<SurfaceFace> out;
  for (const auto& [key, value] : seen)
    if (value.first == 1) out.push_back(value.second);
  return out;
}

std::vector<SurfaceFace> faces_in_box(const std::vector<SurfaceFace>& faces,
                                      const std::vector<Eigen::Vector3d>& vertices, const Eigen::Vector3d& lo,
                                      const Eigen::Vector3d& hi, double tol) {
  std::vector<SurfaceFace> out;
  for (const auto& f : faces) {
    bool all = true;
    for (int a = 0; a < face_node_count(f); ++a) all = all && inside(vertices[f[a]], lo, hi, tol);
    if (all) out.push_back(f);
  }
  return out;
}

std::vector<int> vertices_in_box(const std::vector<Eigen::Vector3d>& vertices, const Eigen::Vector3d& lo,
                                 const Eigen::Vector3d& hi, double tol) {
  std::vector<int> nodes;
  for (int i = 0; i < static_cast<int>(vertices.size()); ++i)
    if (inside(vertices[i], lo, hi, tol)) nodes.push_back(i);
  return nodes;
}

}  // namespace tetfsi::solid
