#include "apps/mpm/membrane_shapes.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>

namespace tetfsi::mpm_setup {
namespace {

constexpr double kPi = 3.14159265358979323846;

int count(double length, double size, int at_least) {
  return std::max(at_least, static_cast<int>(std::lround(length / size)));
}
int even(int n) { return n + (n % 2); }

}  // namespace

void tangent_frame(const Vec3& n_in, Vec3& e1, Vec3& e2) {
  const Vec3 n = n_in.normalized();
  const Vec3 seed = std::abs(n[0]) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = (seed - seed.dot(n) * n).normalized();
  e2 = n.cross(e1);
}

QuadMesh disc_mesh(const Vec3& center, const Vec3& n, double R, double size) {
  Vec3 e1, e2;
  tangent_frame(n, e1, e2);
  const int m = even(count(2 * R, size, 2));
  QuadMesh q;
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= m; ++i) {
      const double p1 = -1 + 2.0 * i / m, p2 = -1 + 2.0 * j / m, r = std::hypot(p1, p2);
      const double s = r > 0 ? std::max(std::abs(p1), std::abs(p2)) / r : 0.0;
      q.nodes.push_back(center + R * s * (p1 * e1 + p2 * e2));
    }
  auto id = [m](int i, int j) { return i + (m + 1) * j; };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) q.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return q;
}

QuadMesh cylinder_mesh(const Vec3& base, const Vec3& axis, double R, double size) {
  Vec3 e1, e2;
  tangent_frame(axis, e1, e2);
  const int nc = 4 * count(2 * kPi * R / 4, size, 1), na = count(axis.norm(), size, 1);
  QuadMesh q;
  for (int k = 0; k <= na; ++k)
    for (int i = 0; i < nc; ++i) {
      const double t = 2 * kPi * i / nc;
      q.nodes.push_back(base + R * (std::cos(t) * e1 + std::sin(t) * e2) + (double(k) / na) * axis);
    }
  for (int k = 0; k < na; ++k)
    for (int i = 0; i < nc; ++i) {
      const int i1 = (i + 1) % nc;
      q.quads.push_back({i + nc * k, i1 + nc * k, i1 + nc * (k + 1), i + nc * (k + 1)});
    }
  return q;
}

QuadMesh box_tube_mesh(const Vec3& base, int ax, double a, double b, double length, double size) {
  const int ny = count(b, size, 1), nx = count(a, size, 1), nz = count(length, size, 1);
  std::vector<Eigen::Vector2d> q1;  // first quadrant, (a, 0) to (0, b) inclusive
  for (int j = 0; j <= ny; ++j) q1.emplace_back(a, b * j / ny);
  for (int i = nx - 1; i >= 0; --i) q1.emplace_back(a * i / nx, b);
  std::vector<Eigen::Vector2d> loop;
  const int n1 = static_cast<int>(q1.size()) - 1;
  for (int k = 0; k < n1; ++k) loop.push_back(q1[k]);
  for (int k = n1; k > 0; --k) loop.emplace_back(0.0 - q1[k][0], q1[k][1]);
  for (int k = 0; k < n1; ++k) loop.emplace_back(0.0 - q1[k][0], 0.0 - q1[k][1]);
  for (int k = n1; k > 0; --k) loop.emplace_back(q1[k][0], 0.0 - q1[k][1]);
  const int np = static_cast<int>(loop.size()), t1 = (ax + 1) % 3, t2 = (ax + 2) % 3;
  QuadMesh m;
  for (int k = 0; k <= nz; ++k)
    for (const auto& p : loop) {
      Vec3 x = base;
      x[t1] += p[0];
      x[t2] += p[1];
      x[ax] = base[ax] + length * k / nz;
      m.nodes.push_back(x);
    }
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < np; ++i) {
      const int i1 = (i + 1) % np;
      m.quads.push_back({i + np * k, i1 + np * k, i1 + np * (k + 1), i + np * (k + 1)});
    }
  return m;
}

QuadMesh box_surface_mesh(const Vec3& center, const Vec3& size, double element) {
  std::array<int, 3> n;
  for (int a = 0; a < 3; ++a) n[a] = count(size[a], element, 1);
  std::vector<int> id(std::size_t(n[0] + 1) * (n[1] + 1) * (n[2] + 1), -1);
  auto flat = [&](const std::array<int, 3>& c) { return c[0] + (n[0] + 1) * (c[1] + (n[1] + 1) * c[2]); };
  QuadMesh m;
  auto node = [&](const std::array<int, 3>& c) {
    int& k = id[flat(c)];
    if (k < 0) {
      Vec3 x;
      for (int a = 0; a < 3; ++a) x[a] = center[a] - 0.5 * size[a] + size[a] * c[a] / n[a];
      k = static_cast<int>(m.nodes.size());
      m.nodes.push_back(x);
    }
    return k;
  };
  for (int ax = 0; ax < 3; ++ax)
    for (int side = 0; side < 2; ++side) {
      const int t1 = (ax + 1) % 3, t2 = (ax + 2) % 3;
      for (int j = 0; j < n[t2]; ++j)
        for (int i = 0; i < n[t1]; ++i) {
          auto c = [&](int di, int dj) {
            std::array<int, 3> p;
            p[ax] = side * n[ax];
            p[t1] = i + di;
            p[t2] = j + dj;
            return node(p);
          };
          if (side == 1)
            m.quads.push_back({c(0, 0), c(1, 0), c(1, 1), c(0, 1)});
          else
            m.quads.push_back({c(0, 0), c(0, 1), c(1, 1), c(1, 0)});
        }
    }
  return m;
}

QuadMesh sphere_mesh(const Vec3& center, double R, double size) {
  const int n = even(count(0.5 * kPi * R, size, 2));
  QuadMesh m = box_surface_mesh(Vec3::Zero(), Vec3(2, 2, 2), 2.0 / n);
  for (auto& x : m.nodes) {
    for (int a = 0; a < 3; ++a) x[a] = std::tan(0.25 * kPi * x[a]);
    x = center + R * x.normalized();
  }
  return m;
}

QuadMesh triangles_to_quads(const mesh::SurfaceMesh& s) {
  QuadMesh m;
  m.nodes = s.vertices;
  std::map<std::pair<int, int>, int> mid;
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    const int k = static_cast<int>(m.nodes.size());
    m.nodes.push_back(0.5 * (s.vertices[a] + s.vertices[b]));
    mid.emplace(key, k);
    return k;
  };
  std::vector<std::array<int, 3>> mids;
  for (const auto& t : s.triangles) mids.push_back({midpoint(t[0], t[1]), midpoint(t[1], t[2]), midpoint(t[2], t[0])});
  for (std::size_t f = 0; f < s.triangles.size(); ++f) {
    const auto& t = s.triangles[f];
    const int g = static_cast<int>(m.nodes.size());
    m.nodes.push_back((s.vertices[t[0]] + s.vertices[t[1]] + s.vertices[t[2]]) / 3.0);
    const auto& md = mids[f];  // ab, bc, ca
    m.quads.push_back({t[0], md[0], g, md[2]});
    m.quads.push_back({t[1], md[1], g, md[0]});
    m.quads.push_back({t[2], md[2], g, md[1]});
  }
  return m;
}

QuadMesh clip(const QuadMesh& m, const std::vector<SymmetryPlane>& planes, double tol) {
  if (planes.empty()) return m;
  auto kept = [&](const Vec3& x) {
    for (const auto& p : planes)
      if (x[p.axis] < p.position - tol) return false;
    return true;
  };
  std::vector<int> map(m.nodes.size(), -1);
  std::vector<std::array<int, 4>> quads;
  for (const auto& q : m.quads) {
    bool keep = true;
    for (int k : q) keep = keep && kept(m.nodes[k]);
    if (!keep) continue;
    for (int k : q) map[k] = 0;
    quads.push_back(q);
  }
  QuadMesh out;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (map[i] == 0) {
      map[i] = static_cast<int>(out.nodes.size());
      out.nodes.push_back(m.nodes[i]);
    }
  for (auto& q : quads) {
    for (int& k : q) k = map[k];
    out.quads.push_back(q);
  }
  return out;
}

namespace {
std::map<std::pair<int, int>, std::array<int, 2>> edge_uses(const std::vector<std::array<int, 4>>& quads) {
  // key: (min, max) node; value: uses in the direction min -> max, in the other direction.
  std::map<std::pair<int, int>, std::array<int, 2>> e;
  for (const auto& q : quads)
    for (int k = 0; k < 4; ++k) {
      const int a = q[k], b = q[(k + 1) % 4];
      ++e[std::minmax(a, b)][a < b ? 0 : 1];
    }
  return e;
}
}  // namespace

std::vector<std::array<int, 2>> open_edges(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& quads,
                                           const std::vector<SymmetryPlane>& planes, double tol) {
  std::vector<std::array<int, 2>> out;
  for (const auto& [key, uses] : edge_uses(quads)) {
    if (uses[0] + uses[1] != 1) continue;
    bool in_plane = false;
    for (const auto& p : planes)
      in_plane = in_plane || (std::abs(nodes[key.first][p.axis] - p.position) <= tol &&
                              std::abs(nodes[key.second][p.axis] - p.position) <= tol);
    if (!in_plane) out.push_back({key.first, key.second});
  }
  return out;
}

int non_manifold_or_misoriented_edges(const std::vector<std::array<int, 4>>& quads) {
  int bad = 0;
  for (const auto& [key, uses] : edge_uses(quads)) bad += uses[0] > 1 || uses[1] > 1;
  return bad;
}

double enclosed_volume(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& quads,
                       const std::vector<SymmetryPlane>& planes) {
  Vec3 o = Vec3::Zero();
  for (const auto& p : planes) o[p.axis] = p.position;
  double v = 0;
  for (const auto& q : quads) {
    const Vec3 a = nodes[q[0]] - o, b = nodes[q[1]] - o, c = nodes[q[2]] - o, d = nodes[q[3]] - o;
    v += a.dot(b.cross(c)) + a.dot(c.cross(d));
  }
  return v / 6;
}

}  // namespace tetfsi::mpm_setup
