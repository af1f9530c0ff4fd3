/// @file primitives.cpp
#include "mesh/primitives.hpp"

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "mesh/complex_mesher.hpp"  // MeshError

namespace tetfsi::mesh {

SurfaceMesh make_box(const Eigen::Vector3d& extents) {
  if (!(extents.array() > 0.0).all() || !extents.allFinite())
    throw MeshError("box: every extent must be > 0");
  const Eigen::Vector3d h = 0.5 * extents;
  SurfaceMesh s;
  // Vertex i has x = +h if bit 0 of i is set, y if bit 1, z if bit 2.
  for (int i = 0; i < 8; ++i)
    s.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Two triangles per face, counter-clockwise seen from outside.
  s.triangles = {{0, 2, 3}, {0, 3, 1},   // z = -h
                 {4, 5, 7}, {4, 7, 6},   // z = +h
                 {0, 1, 5}, {0, 5, 4},   // y = -h
                 {2, 6, 7}, {2, 7, 3},   // y = +h
                 {0, 4, 6}, {0, 6, 2},   // x = -h
                 {1, 3, 7}, {1, 7, 5}};  // x = +h
  return s;
}

SurfaceMesh make_sphere(double radius, int subdivisions) {
  if (!(radius > 0.0) || !std::isfinite(radius)) throw MeshError("sphere: radius must be > 0");
  if (subdivisions < 0 || subdivisions > 7) throw MeshError("sphere: subdivisions must be in [0, 7]");
  // Icosahedron: vertices (0, +-1, +-p), (+-1, +-p, 0), (+-p, 0, +-1), p the golden ratio.
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  SurfaceMesh s;
  s.vertices = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : s.vertices) v.normalize();
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;  // edge (min, max) -> new vertex
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      s.vertices.push_back((s.vertices[a] + s.vertices[b]).normalized());
      return midpoint[key] = s.num_vertices() - 1;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(4 * s.triangles.size());
    for (const auto& t : s.triangles) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    s.triangles = std::move(next);
  }
  for (auto& v : s.vertices) v *= radius;
  return s;
}

SurfaceMesh make_cylinder(double radius, double length, int segments) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !(length > 0.0) || !std::isfinite(length))
    throw MeshError("cylinder: radius and length must be > 0");
  if (segments < 3) throw MeshError("cylinder: segments must be >= 3");
  const double kPi = std::acos(-1.0);
  SurfaceMesh s;
  // Vertex 0: bottom centre, 1: top centre, 2 + 2i: bottom ring, 3 + 2i: top ring (angle 2 pi i / n).
  s.vertices = {{0, 0, -0.5 * length}, {0, 0, 0.5 * length}};
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * kPi * i / segments;
    s.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), -0.5 * length);
    s.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), 0.5 * length);
  }
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    const int b0 = 2 + 2 * i, t0 = 3 + 2 * i, b1 = 2 + 2 * j, t1 = 3 + 2 * j;
    s.triangles.push_back({0, b1, b0});  // bottom cap, normal -z
    s.triangles.push_back({1, t0, t1});  // top cap, normal +z
    s.triangles.push_back({b0, b1, t1});  // side, normal radial
    s.triangles.push_back({b0, t1, t0});
  }
  return s;
}

SurfaceMesh make_bowl(double radius, double thickness, int segments, int rings) {
  if (!(radius > 0.0) || !std::isfinite(radius) || !(thickness > 0.0) || !(thickness < radius))
    throw MeshError("bowl: radius must be > 0 and thickness in (0, radius)");
  if (segments < 3 || rings < 1) throw MeshError("bowl: segments must be >= 3 and rings >= 1");
  const double kPi = std::acos(-1.0);
  SurfaceMesh s;
  // Vertex 0: outer pole, 1: inner pole; then per ring k = 1..rings and angle j the outer vertex at
  // 2 + 2 ((k − 1) segments + j) and the inner one after it.
  s.vertices = {{0, -radius, 0}, {0, -(radius - thickness), 0}};
  for (int k = 1; k <= rings; ++k) {
    const double theta = 0.5 * kPi * k / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * kPi * j / segments;
      const Eigen::Vector3d dir(std::sin(theta) * std::cos(phi), -std::cos(theta), std::sin(theta) * std::sin(phi));
      s.vertices.push_back(radius * dir);
      s.vertices.push_back((radius - thickness) * dir);
    }
  }
  const auto at = [&](int k, int j, int inner) { return k == 0 ? inner : 2 + 2 * ((k - 1) * segments + j % segments) + inner; };
  // Each triangle is oriented by where its outward normal must point: away from the centre on the
  // outer surface, toward it on the inner one, +y on the rim.
  const auto add = [&](int a, int b, int c, const Eigen::Vector3d& outward) {
    const Eigen::Vector3d n = (s.vertices[b] - s.vertices[a]).cross(s.vertices[c] - s.vertices[a]);
    if (n.dot(outward) >= 0) s.triangles.push_back({a, b, c});
    else s.triangles.push_back({a, c, b});
  };
  for (int inner = 0; inner < 2; ++inner)
    for (int k = 0; k < rings; ++k)
      for (int j = 0; j < segments; ++j) {
        const int a = at(k, j, inner), b = at(k, j + 1, inner), c = at(k + 1, j, inner), d = at(k + 1, j + 1, inner);
        const Eigen::Vector3d centre = (s.vertices[a] + s.vertices[c] + s.vertices[d]) / 3.0;
        const Eigen::Vector3d outward = inner ? Eigen::Vector3d(-centre) : centre;
        if (k > 0) add(a, b, d, outward);
        add(a, d, c, outward);
      }
  for (int j = 0; j < segments; ++j) {  // the rim
    const int a = at(rings, j, 0), b = at(rings, j + 1, 0), c = at(rings, j, 1), d = at(rings, j + 1, 1);
    add(a, b, d, Eigen::Vector3d::UnitY());
    add(a, d, c, Eigen::Vector3d::UnitY());
  }
  return s;
}

SurfaceMesh make_sheet(double width, double depth, double thickness) {
  if (!(width > 0.0) || !(depth > 0.0) || !(thickness > 0.0))
    throw MeshError("sheet: width, depth and thickness must be > 0");
  return make_box(Eigen::Vector3d(width, depth, thickness));
}

}  // namespace tetfsi::mesh
