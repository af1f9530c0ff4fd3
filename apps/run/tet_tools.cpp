#include "apps/run/tet_tools.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <Eigen/Dense>

namespace tetfsi::run {

TetQuality tet_quality(const mesh::TetMesh& m) {
  TetQuality q;
  q.tets = m.num_tets();
  if (m.tets.empty()) return q;
  q.min_dihedral_deg = 180;
  q.min_volume = std::numeric_limits<double>::max();
  static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Vector3d p[4];
    for (int k = 0; k < 4; ++k) p[k] = m.vertices[m.tets[t][k]];
    // Dihedral angle at edge (a, b): angle between the normals of the two faces holding it,
    // each face being (a, b, c) with c one of the other two vertices.
    for (const auto& e : edges) {
      int o[2], n = 0;
      for (int k = 0; k < 4; ++k)
        if (k != e[0] && k != e[1]) o[n++] = k;
      const Eigen::Vector3d ab = (p[e[1]] - p[e[0]]).normalized();
      Eigen::Vector3d u = p[o[0]] - p[e[0]], v = p[o[1]] - p[e[0]];
      u -= u.dot(ab) * ab;
      v -= v.dot(ab) * ab;
      const double c = std::clamp(u.normalized().dot(v.normalized()), -1.0, 1.0);
      const double a = std::acos(c) * 180.0 / M_PI;
      q.min_dihedral_deg = std::min(q.min_dihedral_deg, a);
      q.max_dihedral_deg = std::max(q.max_dihedral_deg, a);
    }
    // Circumradius: centre c solves 2 (p_i - p_0) . c = |p_i|^2 - |p_0|^2.
    Eigen::Matrix3d A;
    Eigen::Vector3d b;
    double shortest = std::numeric_limits<double>::max();
    for (int i = 1; i < 4; ++i) {
      A.row(i - 1) = 2 * (p[i] - p[0]).transpose();
      b[i - 1] = p[i].squaredNorm() - p[0].squaredNorm();
    }
    for (const auto& e : edges) shortest = std::min(shortest, (p[e[0]] - p[e[1]]).norm());
    const Eigen::Vector3d c = A.fullPivLu().solve(b);
    q.max_radius_edge = std::max(q.max_radius_edge, (c - p[0]).norm() / shortest);
    q.min_volume = std::min(q.min_volume, mesh::signed_volume(m, t));
  }
  return q;
}

mesh::TetMesh extract_subdomain(const mesh::TetMesh& m, int subdomain) {
  mesh::TetMesh out;
  std::vector<int> map(m.vertices.size(), -1);
  for (int t = 0; t < m.num_tets(); ++t) {
    const int label = m.subdomain.empty() ? subdomain : m.subdomain[t];
    if (label != subdomain) continue;
    std::array<int, 4> tet;
    for (int k = 0; k < 4; ++k) {
      int& v = map[m.tets[t][k]];
      if (v < 0) {
        v = out.num_vertices();
        out.vertices.push_back(m.vertices[m.tets[t][k]]);
      }
      tet[k] = v;
    }
    out.tets.push_back(tet);
    out.subdomain.push_back(subdomain);
  }
  return out;
}

mesh::SurfaceMesh boundary_surface(const mesh::TetMesh& m) {
  // Faces opposite each vertex, ordered so that (b - a) x (c - a) points away from that vertex.
  static const int faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> count;
  for (const auto& t : m.tets)
    for (const auto& f : faces) {
      std::array<int, 3> tri{t[f[0]], t[f[1]], t[f[2]]};
      auto key = tri;
      std::sort(key.begin(), key.end());
      auto& entry = count[key];
      ++entry.first;
      entry.second = tri;
    }
  mesh::SurfaceMesh s;
  std::vector<int> map(m.vertices.size(), -1);
  for (const auto& [key, entry] : count) {
    if (entry.first != 1) continue;
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      int& v = map[entry.second[k]];
      if (v < 0) {
        v = s.num_vertices();
        s.vertices.push_back(m.vertices[entry.second[k]]);
      }
      tri[k] = v;
    }
    s.triangles.push_back(tri);
  }
  return s;
}

}  // namespace tetfsi::run
