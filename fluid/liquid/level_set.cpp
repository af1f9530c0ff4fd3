#include "fluid/liquid/level_set.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "fluid/liquid/cut_tet.hpp"

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

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

/// Builds surfaces whose vertices are mesh nodes or edge crossings, each made once.
class SurfaceBuilder {
 public:
  SurfaceBuilder(const FluidMesh& mesh, const Eigen::VectorXd& phi) : mesh_(mesh), phi_(phi) {}

  /// Vertex where the edge between liquid node a and air node b crosses zero.
  int crossing(int a, int b) {
    auto [it, added] = crossing_.emplace(edge_key(a, b), surface.num_vertices());
    if (added) {
      const double theta = crossing_fraction(phi_[a], phi_[b]);
      surface.vertices.push_back(mesh_.nodes[a] + theta * (mesh_.nodes[b] - mesh_.nodes[a]));
      edge.push_back({a, b});
      weight.push_back(theta);
    }
    return it->second;
  }
  /// Vertex at node a.
  int node(int a) {
    auto [it, added] = node_.emplace(a, surface.num_vertices());
    if (added) {
      surface.vertices.push_back(mesh_.nodes[a]);
      edge.push_back({a, a});
      weight.push_back(0.0);
    }
    return it->second;
  }
  /// Adds triangle (i, j, k), flipped if its normal points against `direction`.
  void triangle(int i, int j, int k, const Eigen::Vector3d& direction) {
    const auto& x = surface.vertices;
    if ((x[j] - x[i]).cross(x[k] - x[i]).dot(direction) < 0) std::swap(j, k);
    surface.triangles.push_back({i, j, k});
  }

  mesh::SurfaceMesh surface;
  std::vector<std::array<int, 2>> edge;  ///< per vertex: its edge (a == b for a node)
  std::vector<double> weight;            ///< per vertex: theta along the edge from its first node

 private:
  const FluidMesh& mesh_;
  const Eigen::VectorXd& phi_;
  std::unordered_map<std::uint64_t, int> crossing_;
  std::unordered_map<int, int> node_;
};

void add_zero_set(const FluidMesh& mesh, const Eigen::VectorXd& phi, SurfaceBuilder& out) {
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto& tet = mesh.tets[t];
    int liquid[4], air[4], nl = 0, na = 0;
    for (int k = 0; k < 4; ++k) (phi[tet[k]] < 0.0 ? liquid[nl++] : air[na++]) = tet[k];
    if (nl == 0 || nl == 4) continue;
    Eigen::Vector3d grad_phi = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) grad_phi += phi[tet[k]] * mesh.grad[t][k];
    if (nl == 1) {
      out.triangle(out.crossing(liquid[0], air[0]), out.crossing(liquid[0], air[1]), out.crossing(liquid[0], air[2]),
                   grad_phi);
    } else if (nl == 3) {
      out.triangle(out.crossing(liquid[0], air[0]), out.crossing(liquid[1], air[0]), out.crossing(liquid[2], air[0]),
                   grad_phi);
    } else {  // the quad X_ac, X_ad, X_bd, X_bc (consecutive vertices share a face of the tet)
      const int ac = out.crossing(liquid[0], air[0]), ad = out.crossing(liquid[0], air[1]);
      const int bd = out.crossing(liquid[1], air[1]), bc = out.crossing(liquid[1], air[0]);
      out.triangle(ac, ad, bd, grad_phi);
      out.triangle(ac, bd, bc, grad_phi);
    }
  }
}

/// Uniform grid of triangle bounding boxes for distance queries within `reach`.
class TriangleGrid {
 public:
  TriangleGrid(const mesh::SurfaceMesh& s, double reach) : s_(s), cell_(reach) {
    lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
    hi_ = -lo_;
    for (const auto& v : s.vertices) {
      lo_ = lo_.cwiseMin(v);
      hi_ = hi_.cwiseMax(v);
    }
    for (int c = 0; c < 3; ++c) dims_[c] = std::max(1, static_cast<int>(std::ceil((hi_[c] - lo_[c]) / cell_)) + 1);
    const long long cells = static_cast<long long>(dims_[0]) * dims_[1] * dims_[2];
    if (cells > 8LL * std::max<long long>(1, s.num_triangles()) + 1024) {  // keep memory bounded
      cell_ *= std::cbrt(static_cast<double>(cells) / (8.0 * std::max(1, s.num_triangles()) + 1024));
      for (int c = 0; c < 3; ++c) dims_[c] = std::max(1, static_cast<int>(std::ceil((hi_[c] - lo_[c]) / cell_)) + 1);
    }
    start_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    std::vector<std::array<Eigen::Vector3i, 2>> range(s.num_triangles());
    for (int f = 0; f < s.num_triangles(); ++f) {
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
    for (int f = 0; f < s.num_triangles(); ++f)
      for_cells(range[f][0], range[f][1], [&](size_t c) { items_[fill[c]++] = f; });
    mark_open_features();
  }

  /// Distance from x to the nearest triangle, or `reach` if none is nearer. A triangle with an
  /// edge on the zero set's open boundary (where the surface meets a wall or a solid) counts as
  /// continued across it in its plane (strip_distance2): the surface goes on across the wall, so
  /// that a liquid resting against a wall that leans outward (a bowl) keeps a linear phi next to it
  /// and the next transfer does not move its waterline (the distance to the cut-off surface grew
  /// towards its rim and drained such a layer). The continued distance is taken no smaller than
  /// half the distance to the triangle itself (a node that sees the surface edge-on across a thin
  /// wall). Continuous in x, so round-off in phi does not switch a node between the two.
  double distance(const Eigen::Vector3d& x, double reach) const {
    double best2 = reach * reach;
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(reach);
    if (((x + r).array() < lo_.array()).any() || ((x - r).array() > hi_.array()).any()) return reach;
    for_cells(cell_of(x - r), cell_of(x + r), [&](size_t c) {
      for (int i = start_[c]; i < start_[c + 1]; ++i) {
        const int t = items_[i];
        const auto& f = s_.triangles[t];
        const Eigen::Vector3d &a = s_.vertices[f[0]], &b = s_.vertices[f[1]], &c = s_.vertices[f[2]];
        const double d2 = (closest_on_triangle(x, a, b, c) - x).squaredNorm();
        best2 = std::min(best2, d2);
        for (int e = 0; e < 3; ++e)  // the triangle continued across its open edges
          if (open_[t] >> e & 1) {
            const Eigen::Vector3d& p = s_.vertices[f[e]];
            const Eigen::Vector3d& q = s_.vertices[f[(e + 1) % 3]];
            const Eigen::Vector3d& r = s_.vertices[f[(e + 2) % 3]];
            best2 = std::min(best2, std::max(strip_distance2(x, p, q, r), 0.25 * d2));
          }
      }
    });
    return std::sqrt(best2);
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
        for (int i = a[0]; i <= b[0]; ++i)
          f((static_cast<size_t>(k) * dims_[1] + j) * dims_[0] + i);
  }

  /// Per triangle, bit e set if its edge e (vertices e, e + 1 mod 3) is on the zero set's boundary
  /// (used by this triangle only): where the surface meets a wall or a solid.
  void mark_open_features() {
    std::unordered_map<std::uint64_t, int> uses;
    for (const auto& f : s_.triangles)
      for (int k = 0; k < 3; ++k) ++uses[edge_key(f[k], f[(k + 1) % 3])];
    open_.assign(s_.num_triangles(), 0);
    for (int t = 0; t < s_.num_triangles(); ++t)
      for (int e = 0; e < 3; ++e)
        if (uses[edge_key(s_.triangles[t][e], s_.triangles[t][(e + 1) % 3])] == 1) open_[t] |= 1 << e;
  }

  const mesh::SurfaceMesh& s_;
  std::vector<unsigned char> open_;
  double cell_;
  Eigen::Vector3d lo_, hi_;
  int dims_[3] = {1, 1, 1};
  std::vector<int> start_, items_;
};

/// Per-tet liquid volumes summed in tet order (deterministic for any thread count).
double volume_of(const FluidMesh& mesh, const Eigen::VectorXd& phi, double shift, std::vector<double>& scratch) {
  scratch.resize(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    const auto& tet = mesh.tets[t];
    scratch[t] = mesh.volume[t] * liquid_fraction({phi[tet[0]] + shift, phi[tet[1]] + shift, phi[tet[2]] + shift,
                                                   phi[tet[3]] + shift});
  });
  double v = 0.0;
  for (double x : scratch) v += x;
  return v;
}

}  // namespace

double box_distance(const Eigen::Vector3d& x, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d q = (x - 0.5 * (lo + hi)).cwiseAbs() - 0.5 * (hi - lo);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Eigen::VectorXd sample_level_set(const FluidMesh& mesh, const std::function<double(const Eigen::Vector3d&)>& sdf) {
  Eigen::VectorXd phi(mesh.num_nodes());
  for (int i = 0; i < mesh.num_nodes(); ++i) phi[i] = sdf(mesh.nodes[i]);
  return phi;
}

double liquid_volume(const FluidMesh& mesh, const Eigen::VectorXd& phi) {
  std::vector<double> scratch;
  return volume_of(mesh, phi, 0.0, scratch);
}

mesh::SurfaceMesh zero_set(const FluidMesh& mesh, const Eigen::VectorXd& phi, std::vector<std::array<int, 2>>* vertex_edge) {
  SurfaceBuilder b(mesh, phi);
  add_zero_set(mesh, phi, b);
  if (vertex_edge) *vertex_edge = b.edge;
  return std::move(b.surface);
}

mesh::SurfaceMesh liquid_surface(const FluidMesh& mesh, const Eigen::VectorXd& phi, const TetVectors& velocity,
                                 std::vector<Eigen::Vector3d>* vertex_velocity) {
  SurfaceBuilder b(mesh, phi);
  add_zero_set(mesh, phi, b);
  for (const BoundaryFace& f : mesh.boundary_faces) {
    std::vector<int> polygon;  // the wet part of the face, walking its edges
    for (int k = 0; k < 3; ++k) {
      const int a = f.nodes[k], c = f.nodes[(k + 1) % 3];
      if (phi[a] < 0.0) polygon.push_back(b.node(a));
      if ((phi[a] < 0.0) != (phi[c] < 0.0)) polygon.push_back(phi[a] < 0.0 ? b.crossing(a, c) : b.crossing(c, a));
    }
    for (size_t k = 2; k < polygon.size(); ++k) b.triangle(polygon[0], polygon[k - 1], polygon[k], f.normal);
  }
  if (vertex_velocity) {
    const TetVectors nodal = average_to_nodes(mesh, velocity);
    vertex_velocity->resize(b.surface.num_vertices());
    for (int v = 0; v < b.surface.num_vertices(); ++v) {
      const auto [a, c] = b.edge[v];
      (*vertex_velocity)[v] = (1.0 - b.weight[v]) * nodal[a] + b.weight[v] * nodal[c];
    }
  }
  return std::move(b.surface);
}

void snap_to_surface(const FluidMesh& mesh, Eigen::VectorXd& phi) {
  const double snap = 1e-9 * mesh.mean_edge_length();
  for (double& v : phi)
    if (std::abs(v) < snap) v = 0.0;
}

void wet_enclosed_zeros(const FluidMesh& mesh, Eigen::VectorXd& phi) {
  // Candidates: the nodes at 0 with no air neighbour; wet: those a path of candidates joins to a
  // liquid node (a corner of the floor may see only other nodes of the walls).
  auto neighbours = [&](int i, auto&& f) {
    for (int t : mesh.node_tets[i])
      for (int j : mesh.tets[t])
        if (j != i) f(j);
  };
  std::vector<char> candidate(mesh.num_nodes(), 0);
  std::vector<int> front;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (phi[i] != 0.0) continue;
    bool air = false, liquid = false;
    neighbours(i, [&](int j) {
      air = air || phi[j] > 0.0;
      liquid = liquid || phi[j] < 0.0;
    });
    candidate[i] = !air;
    if (!air && liquid) front.push_back(i);
  }
  std::vector<int> wet;
  for (int i : front) candidate[i] = 0;
  while (!front.empty()) {
    const int i = front.back();
    front.pop_back();
    wet.push_back(i);
    neighbours(i, [&](int j) {
      if (!candidate[j]) return;
      candidate[j] = 0;
      front.push_back(j);
    });
  }
  for (int i : wet) phi[i] = -std::numeric_limits<double>::min();
}

void redistance(const FluidMesh& mesh, Eigen::VectorXd& phi, double band, bool keep_cut_tets) {
  if (!(band > 0.0)) throw std::invalid_argument("redistance: the band must be positive");
  if (phi.size() != mesh.num_nodes()) throw std::invalid_argument("redistance: phi does not match the mesh");
  const mesh::SurfaceMesh s = zero_set(mesh, phi);
  std::vector<char> keep(keep_cut_tets ? phi.size() : 0, 0);
  if (keep_cut_tets)
    for (const auto& tet : mesh.tets) {
      int nl = 0;
      for (int k = 0; k < 4; ++k) nl += phi[tet[k]] < 0.0;
      if (nl > 0 && nl < 4)
        for (int k = 0; k < 4; ++k) keep[tet[k]] = 1;
    }
  if (s.num_triangles() == 0) {
    for (Eigen::Index i = 0; i < phi.size(); ++i) phi[i] = phi[i] < 0.0 ? -band : band;
    return;
  }
  const TriangleGrid grid(s, 0.5 * band);
  Eigen::VectorXd out(phi.size());
  // Only nodes inside the band need the query: a node that had the clamped value +-band and
  // whose foot stayed where every value was clamped still reads +-band, and is at least a band
  // from the surface up to the step's motion, which the clamp does not see.
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    if (keep_cut_tets && keep[i]) {
      out[i] = phi[i];
      return;
    }
    const double d = std::abs(phi[i]) >= band ? band : grid.distance(mesh.nodes[i], band);
    out[i] = phi[i] < 0.0 ? -d : d;
  });
  // A liquid node on the surface itself (d = 0) would turn to air: keep it liquid by a hair.
  for (Eigen::Index i = 0; i < phi.size(); ++i)
    if (phi[i] < 0.0 && !(out[i] < 0.0)) out[i] = -std::numeric_limits<double>::min();
  phi = std::move(out);
}

double restore_volume(const FluidMesh& mesh, Eigen::VectorXd& phi, double target, double relative_tolerance) {
  if (!(target >= 0.0)) throw std::invalid_argument("restore_volume: the target volume must be >= 0");
  std::vector<double> scratch;
  auto excess = [&](double shift) { return volume_of(mesh, phi, shift, scratch) - target; };
  const double tol = relative_tolerance * std::max(target, 1e-300);
  double f0 = excess(0.0);
  if (std::abs(f0) <= tol) return 0.0;
  // Newton: dV/d(shift) = -(area of the zero set) for a distance function; a few steps suffice.
  double area = 0.0;
  {
    const mesh::SurfaceMesh z = zero_set(mesh, phi);
    for (const auto& t : z.triangles)
      area += 0.5 * (z.vertices[t[1]] - z.vertices[t[0]]).cross(z.vertices[t[2]] - z.vertices[t[0]]).norm();
  }
  if (area > 0.0) {
    double shift = 0.0, f = f0;
    for (int k = 0; k < 4; ++k) {
      const double next = shift + f / area, fn = excess(next);
      if (!(std::abs(fn) < std::abs(f))) break;
      shift = next;
      f = fn;
      if (std::abs(f) <= tol) {
        phi.array() += shift;
        return shift;
      }
    }
  }
  // Liquid volume falls as phi rises: bracket the root, then secant steps kept inside the bracket.
  const double step0 = 0.01 * mesh.mean_edge_length();
  double a = 0.0, fa = f0, b = f0 > 0 ? step0 : -step0, fb = excess(b);
  for (int k = 0; k < 60 && (fa > 0) == (fb > 0); ++k) {
    a = b;
    fa = fb;
    b *= 2.0;
    fb = excess(b);
  }
  if ((fa > 0) == (fb > 0)) return 0.0;  // no bracket (no liquid can be made or removed): leave phi
  // Illinois variant of regula falsi: the endpoint kept twice in a row has its value halved.
  double best = std::abs(fa) < std::abs(fb) ? a : b, fbest = std::min(std::abs(fa), std::abs(fb));
  int kept = 0;
  for (int k = 0; k < 60 && fbest > tol; ++k) {
    const double c = b - fb * (b - a) / (fb - fa);
    const double fc = excess(c);
    if (std::abs(fc) < fbest) {
      best = c;
      fbest = std::abs(fc);
    }
    if ((fc > 0) == (fb > 0)) {
      b = c;
      fb = fc;
      if (kept == -1) fa *= 0.5;
      kept = -1;
    } else {
      a = b;
      fa = fb;
      b = c;
      fb = fc;
      kept = 0;
    }
  }
  phi.array() += best;
  return best;
}

}  // namespace tetfsi::fluid
