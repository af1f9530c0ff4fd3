#include "fluid/liquid/zero_set_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <unordered_map>

#include <tbb/parallel_for.h>

namespace tetfsi::fluid {
namespace {

/// Closest point to p on triangle (a, b, c), by the Voronoi regions of its vertices, edges and face
/// (Ericson, "Real-Time Collision Detection", 2005, sec. 5.1.5). Written here: Eigen has no such
/// query, and CGAL's AABB tree must stay inside mesh/.
Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Squared distance from x to the half-strip that continues triangle (p, q, r) across its edge pq:
/// the points of its plane beyond the line pq, between the normals to pq at p and at q.
double strip_distance2(const Eigen::Vector3d& x, const Eigen::Vector3d& p, const Eigen::Vector3d& q,
                       const Eigen::Vector3d& r) {
  const Eigen::Vector3d e = q - p, n = e.cross(r - p);
  const double length = e.norm(), area2 = n.norm();
  if (!(length > 0.0) || !(area2 > 0.0)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector3d along = e / length, normal = n / area2, out = along.cross(normal);  // out: away from r
  const Eigen::Vector3d d = x - p;
  const double s = d.dot(along), w = d.dot(out), h = d.dot(normal);
  const double ds = s < 0.0 ? s : (s > length ? s - length : 0.0), dw = std::min(w, 0.0);
  return h * h + ds * ds + dw * dw;
}

/// Uniform grid of the bounding boxes of the triangles `which` (cell side `cell`, enlarged if the
/// grid would hold more than 8 cells per triangle): the triangles near a point, for the exact search.
class TriangleBins {
 public:
  TriangleBins(const mesh::SurfaceMesh& s, const std::vector<int>& which, double cell) : cell_(cell) {
    lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
    Eigen::Vector3d hi = -lo_;
    for (const auto& v : s.vertices) {
      lo_ = lo_.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    const double most = 8.0 * which.size() + 1024;
    auto size = [&] {
      for (int c = 0; c < 3; ++c) dims_[c] = std::max(1, static_cast<int>(std::ceil((hi[c] - lo_[c]) / cell_)) + 1);
      return double(dims_[0]) * dims_[1] * dims_[2];
    };
    if (size() > most) {
      cell_ *= std::cbrt(size() / most);
      size();
    }
    start_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    std::vector<std::array<Eigen::Vector3i, 2>> range(s.num_triangles());
    for (int f : which) {
      Eigen::Vector3d a = s.vertices[s.triangles[f][0]], b = a;
      for (int k = 1; k < 3; ++k) {
        a = a.cwiseMin(s.vertices[s.triangles[f][k]]);
        b = b.cwiseMax(s.vertices[s.triangles[f][k]]);
      }
      range[f] = {cell_of(a), cell_of(b)};
      for_cells(range[f][0], range[f][1], [&](size_t c) { ++start_[c + 1]; });
    }
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    items_.resize(start_.back());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (int f : which) for_cells(range[f][0], range[f][1], [&](size_t c) { items_[fill[c]++] = f; });
  }

  /// Calls f(triangle) for every triangle whose box meets the cube of half side r around x (a
  /// triangle may come more than once).
  template <class F>
  void near(const Eigen::Vector3d& x, double r, F&& f) const {
    const Eigen::Vector3d d = Eigen::Vector3d::Constant(r);
    for_cells(cell_of(x - d), cell_of(x + d), [&](size_t c) {
      for (int i = start_[c]; i < start_[c + 1]; ++i) f(items_[i]);
    });
  }

 private:
  Eigen::Vector3i cell_of(const Eigen::Vector3d& x) const {
    Eigen::Vector3i c;
    for (int k = 0; k < 3; ++k)
      c[k] = std::clamp(static_cast<int>(std::floor((x[k] - lo_[k]) / cell_)), 0, dims_[k] - 1);
    return c;
  }
  template <class F>
  void for_cells(const Eigen::Vector3i& a, const Eigen::Vector3i& b, F&& f) const {
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i) f((static_cast<size_t>(k) * dims_[1] + j) * dims_[0] + i);
  }

  double cell_;
  Eigen::Vector3d lo_;
  int dims_[3] = {1, 1, 1};
  std::vector<int> start_, items_;
};

}  // namespace

ZeroSetDistance::ZeroSetDistance(const mesh::SurfaceMesh& surface) : surface_(surface) {
  std::unordered_map<std::uint64_t, int> uses;
  for (const auto& f : surface.triangles)
    for (int k = 0; k < 3; ++k) ++uses[edge_key(f[k], f[(k + 1) % 3])];
  open_.assign(surface.num_triangles(), 0);
  for (int t = 0; t < surface.num_triangles(); ++t)
    for (int e = 0; e < 3; ++e)
      if (uses[edge_key(surface.triangles[t][e], surface.triangles[t][(e + 1) % 3])] == 1) open_[t] |= 1 << e;
}

bool ZeroSetDistance::has_open_edge(int triangle) const { return open_[triangle] != 0; }

double ZeroSetDistance::operator()(int triangle, const Eigen::Vector3d& x) const {
  const auto& f = surface_.triangles[triangle];
  const Eigen::Vector3d &a = surface_.vertices[f[0]], &b = surface_.vertices[f[1]], &c = surface_.vertices[f[2]];
  const double d2 = (closest_on_triangle(x, a, b, c) - x).squaredNorm();
  double best2 = d2;
  for (int e = 0; e < 3; ++e)  // the triangle continued across its open edges
    if (open_[triangle] >> e & 1) {
      const Eigen::Vector3d& p = surface_.vertices[f[e]];
      const Eigen::Vector3d& q = surface_.vertices[f[(e + 1) % 3]];
      const Eigen::Vector3d& r = surface_.vertices[f[(e + 2) % 3]];
      best2 = std::min(best2, std::max(strip_distance2(x, p, q, r), 0.25 * d2));
    }
  return std::sqrt(best2);
}

std::vector<double> propagated_distance(const FluidMesh& mesh, const mesh::SurfaceMesh& surface,
                                        const std::vector<int>& triangle_tet, double reach, double exact_reach,
                                        const std::vector<char>& kept) {
  if (!(reach > 0.0)) throw std::invalid_argument("propagated_distance: the reach must be positive");
  if (!kept.empty() && static_cast<int>(kept.size()) != mesh.num_nodes())
    throw std::invalid_argument("propagated_distance: one kept flag per node expected");
  if (static_cast<int>(triangle_tet.size()) != surface.num_triangles())
    throw std::invalid_argument("propagated_distance: one tet per triangle expected");
  const ZeroSetDistance distance(surface);
  const int n = mesh.num_nodes();
  std::vector<double> best(n, reach);
  std::vector<int> nearest(n, -1);  // the triangle that gives best
  // Min-heap of (distance, node); ties go to the lower node index, so the order is deterministic.
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> front;
  // The triangles around each surface vertex (compressed rows), for the descent below.
  const int nv = surface.num_vertices();
  std::vector<int> ring_start(nv + 1, 0), ring;
  for (const auto& f : surface.triangles)
    for (int v : f) ++ring_start[v + 1];
  for (int v = 0; v < nv; ++v) ring_start[v + 1] += ring_start[v];
  ring.resize(ring_start[nv]);
  {
    std::vector<int> fill(ring_start.begin(), ring_start.end() - 1);
    for (int t = 0; t < surface.num_triangles(); ++t)
      for (int v : surface.triangles[t]) ring[fill[v]++] = t;
  }
  // Descent over the surface: node i moves to a triangle near its nearest one while that is nearer
  // (the nearest point slides along a smooth surface as the node moves): first among the triangles
  // sharing a vertex with it, and where none is nearer, among those sharing a vertex with these
  // (a faceted zero set has shallow local minima that one ring does not leave).
  std::vector<int> seen(surface.num_triangles(), -1);
  int visit = 0;
  auto try_ring = [&](int i, int triangle) {  // true if a triangle around `triangle` is nearer
    bool moved = false;
    for (int v : surface.triangles[triangle])
      for (int k = ring_start[v]; k < ring_start[v + 1]; ++k) {
        const int t = ring[k];
        if (seen[t] == visit) continue;
        seen[t] = visit;
        const double d = distance(t, mesh.nodes[i]);
        if (d < best[i]) {
          best[i] = d;
          nearest[i] = t;
          moved = true;
        }
      }
    return moved;
  };
  auto descend = [&](int i) {
    while (true) {
      ++visit;
      if (try_ring(i, nearest[i])) continue;
      const int from = nearest[i];
      bool moved = false;
      for (int v : surface.triangles[from])
        for (int k = ring_start[v]; k < ring_start[v + 1]; ++k) moved = try_ring(i, ring[k]) || moved;
      if (!moved) return;
    }
  };
  // Offers `triangle` to `node`. A node offered its first triangle, and not reached by it,
  // still descends from it: its nearest triangle may lie within reach where its neighbours' do not.
  auto offer = [&](int node, int triangle) {
    const double d = distance(triangle, mesh.nodes[node]);
    if (d < best[node]) {
      best[node] = d;
      nearest[node] = triangle;
    } else if (nearest[node] < 0) {
      nearest[node] = triangle;
      descend(node);
      if (!(best[node] < reach)) return;
    } else {
      return;
    }
    front.emplace(best[node], node);
  };
  for (int tri = 0; tri < surface.num_triangles(); ++tri)
    for (int node : mesh.tets[triangle_tet[tri]]) offer(node, tri);
  while (!front.empty()) {
    const auto [d, i] = front.top();
    front.pop();
    if (d != best[i]) continue;  // superseded by a nearer triangle
    const bool needed = kept.empty() || !kept[i];
    if (needed && !(best[i] < exact_reach)) descend(i);  // nearer nodes get the exact minimum below
    const int tri = nearest[i];
    for (int t : mesh.node_tets[i])
      for (int j : mesh.tets[t])
        if (nearest[j] != tri) offer(j, tri);
  }
  // Exact where the surface's next motion reads phi: every triangle within the propagated distance
  // (an upper bound) of a node nearer than exact_reach. Strips extend a triangle by at most half
  // its distance, so a triangle with an open edge counts within twice that bound.
  if (exact_reach > 0.0) {
    std::vector<int> all(surface.num_triangles()), open;
    for (int t = 0; t < surface.num_triangles(); ++t) {
      all[t] = t;
      if (distance.has_open_edge(t)) open.push_back(t);
    }
    const TriangleBins bins(surface, all, exact_reach), open_bins(surface, open, exact_reach);
    tbb::parallel_for(0, n, [&](int i) {
      if (!(best[i] < exact_reach) || (!kept.empty() && kept[i])) return;
      const Eigen::Vector3d& x = mesh.nodes[i];
      double d = best[i];
      const auto nearer = [&](int t) { d = std::min(d, distance(t, x)); };
      bins.near(x, best[i], nearer);
      if (!open.empty()) open_bins.near(x, 2.0 * best[i], nearer);
      best[i] = d;
    });
  }
  return best;
}

}  // namespace tetfsi::fluid
