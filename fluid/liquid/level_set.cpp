#include "fluid/liquid/level_set.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "fluid/liquid/cut_tet.hpp"
#include "fluid/liquid/zero_set_distance.hpp"

namespace tetfsi::fluid {
namespace {

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
    triangle_tet.push_back(tet);
  }

  mesh::SurfaceMesh surface;
  std::vector<std::array<int, 2>> edge;  ///< per vertex: its edge (a == b for a node)
  std::vector<double> weight;            ///< per vertex: theta along the edge from its first node
  std::vector<int> triangle_tet;         ///< per triangle: the tet it cuts (-1: a boundary face's part)
  int tet = -1;                          ///< the tet whose triangles are being added

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
    out.tet = t;
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
  SurfaceBuilder zero(mesh, phi);
  add_zero_set(mesh, phi, zero);
  std::vector<char> keep(keep_cut_tets ? phi.size() : 0, 0);
  if (keep_cut_tets)
    for (const auto& tet : mesh.tets) {
      int nl = 0;
      for (int k = 0; k < 4; ++k) nl += phi[tet[k]] < 0.0;
      if (nl > 0 && nl < 4)
        for (int k = 0; k < 4; ++k) keep[tet[k]] = 1;
    }
  if (zero.surface.num_triangles() == 0) {
    for (Eigen::Index i = 0; i < phi.size(); ++i) phi[i] = phi[i] < 0.0 ? -band : band;
    return;
  }
  // Exact in the inner half of the band (where the next steps move the surface), propagated beyond.
  const std::vector<double> distance = propagated_distance(mesh, zero.surface, zero.triangle_tet, band, 0.5 * band, keep);
  Eigen::VectorXd out(phi.size());
  // A node that had the clamped value +-band keeps it: whose foot stayed where every value was
  // clamped still reads +-band, and is at least a band from the surface up to the step's motion,
  // which the clamp does not see.
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    if (keep_cut_tets && keep[i]) {
      out[i] = phi[i];
      return;
    }
    const double d = std::abs(phi[i]) >= band ? band : distance[i];
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
