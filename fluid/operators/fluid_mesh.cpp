#include "fluid/operators/fluid_mesh.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "support/number_text.hpp"

namespace tetfsi::fluid {
namespace {

/// One face of a tet, keyed by its sorted vertex triple (TetMesh vertex ids).
struct FaceRecord {
  std::array<int, 3> key;
  int mesh_tet;
  int local_face;
};

/// Local vertices of the face opposite local vertex k, ordered so that the right-hand normal points
/// out of a positively oriented tet.
constexpr int kFaceVertices[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// The bits of a 21-bit integer spread to every third bit (bit i to bit 3i).
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// The fluid tets of `mesh` (TetMesh tet ids) in Morton (Z-curve) order of their centroids over
/// the mesh's bounding box, ties by id. Numbering the fluid tets, and the nodes as the tets first
/// touch them, along a space-filling curve keeps neighbours close in memory: the point location,
/// interpolation and assembly of every step then read mostly cached data, where the mesher's
/// order (CGAL's cell container) scatters each neighbourhood over the whole arrays.
std::vector<int> fluid_tets_in_curve_order(const mesh::TetMesh& mesh, const std::vector<char>& fluid) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const Eigen::Vector3d& x : mesh.vertices) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Eigen::Vector3d scale = (double((1 << 21) - 1) / (hi - lo).cwiseMax(1e-300).array()).matrix();
  std::vector<std::pair<std::uint64_t, int>> keyed;
  keyed.reserve(mesh.tets.size());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!fluid[t]) continue;
    const auto& v = mesh.tets[t];
    const Eigen::Vector3d c = 0.25 * (mesh.vertices[v[0]] + mesh.vertices[v[1]] + mesh.vertices[v[2]] + mesh.vertices[v[3]]);
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double u = (c[a] - lo[a]) * scale[a];  // a non-finite position is refused later, by its volume
      const double q = std::isfinite(u) ? std::clamp(u, 0.0, double((1 << 21) - 1)) : 0.0;
      key |= spread_bits(static_cast<std::uint64_t>(q)) << a;
    }
    keyed.emplace_back(key, t);
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());  // (key, id) pairs are distinct: deterministic
  std::vector<int> order(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

/// Volumes and hat-function gradients of every fluid tet from fm.nodes: with E = [x1-x0, x2-x0,
/// x3-x0], the rows of E^-1 are grad(phi_1..3), stored (grad(phi_0) = -their sum is computed when
/// read: HatGradients). Throws on a tet of non-positive volume.
void compute_tet_geometry(FluidMesh& fm) {
  const int nf = fm.num_tets();
  fm.volume.resize(nf);
  fm.grad.stored.resize(nf);
  // Each tet on its own (in parallel); the first tet with non-positive volume is found afterwards,
  // so that the error names the same tet whatever the thread count.
  tbb::parallel_for(tbb::blocked_range<int>(0, nf), [&](const tbb::blocked_range<int>& range) {
    for (int t = range.begin(); t < range.end(); ++t) {
      const auto& v = fm.tets[t];
      Eigen::Matrix3d e;
      e.col(0) = fm.nodes[v[1]] - fm.nodes[v[0]];
      e.col(1) = fm.nodes[v[2]] - fm.nodes[v[0]];
      e.col(2) = fm.nodes[v[3]] - fm.nodes[v[0]];
      fm.volume[t] = e.determinant() / 6.0;
      const Eigen::Matrix3d inv = e.inverse();
      for (int k = 0; k < 3; ++k) fm.grad.stored[t][k] = inv.row(k).transpose();  // ∇φ₁, ∇φ₂, ∇φ₃
    }
  });
  for (int t = 0; t < nf; ++t)
    if (!(fm.volume[t] > 0.0))
      throw std::invalid_argument("fluid mesh: fluid tet " + std::to_string(fm.tet_to_mesh_tet[t]) +
                                  " has non-positive volume " + number_text(fm.volume[t]));
}

/// Area and unit outward normal of a boundary face from its nodes' positions.
void set_face_geometry(const std::vector<Eigen::Vector3d>& nodes, BoundaryFace& f) {
  const Eigen::Vector3d n = (nodes[f.nodes[1]] - nodes[f.nodes[0]]).cross(nodes[f.nodes[2]] - nodes[f.nodes[0]]);
  f.area = 0.5 * n.norm();
  f.normal = n.normalized();
}

/// Lumped node volumes sum_t V_t / 4, summed in tet order.
void compute_dual_volumes(FluidMesh& fm) {
  fm.dual_volume.assign(fm.num_nodes(), 0.0);
  for (int t = 0; t < fm.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) fm.dual_volume[fm.tets[t][k]] += 0.25 * fm.volume[t];
}

}  // namespace

double FluidMesh::mean_edge_length() const {
  double sum = 0.0;
  for (const auto& v : tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) sum += (nodes[v[a]] - nodes[v[b]]).norm();
  return tets.empty() ? 0.0 : sum / (6.0 * static_cast<double>(tets.size()));
}

FluidMesh build_fluid_mesh(const mesh::TetMesh& mesh) {
  const int nv = mesh.num_vertices();
  const int nt = mesh.num_tets();
  if (!mesh.subdomain.empty() && static_cast<int>(mesh.subdomain.size()) != nt)
    throw std::invalid_argument("build_fluid_mesh: subdomain has " + std::to_string(mesh.subdomain.size()) +
                                " labels for " + std::to_string(nt) + " tets");
  auto is_fluid = [&](int t) { return mesh.subdomain.empty() || mesh.subdomain[t] == mesh::kFluidSubdomain; };

  FluidMesh fm;
  fm.mesh_vertex_to_node.assign(nv, -1);
  std::vector<int> mesh_tet_to_fluid(nt, -1);
  std::vector<char> fluid(nt, 0);
  for (int t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k)
      if (mesh.tets[t][k] < 0 || mesh.tets[t][k] >= nv)
        throw std::invalid_argument("build_fluid_mesh: tet " + std::to_string(t) + " has vertex index " +
                                    std::to_string(mesh.tets[t][k]) + " out of range");
    fluid[t] = is_fluid(t);
  }
  for (const int t : fluid_tets_in_curve_order(mesh, fluid)) {
    mesh_tet_to_fluid[t] = static_cast<int>(fm.tets.size());
    std::array<int, 4> local{};
    for (int k = 0; k < 4; ++k) {
      int& node = fm.mesh_vertex_to_node[mesh.tets[t][k]];
      if (node < 0) {
        node = static_cast<int>(fm.nodes.size());
        fm.nodes.push_back(mesh.vertices[mesh.tets[t][k]]);
        fm.node_to_mesh_vertex.push_back(mesh.tets[t][k]);
      }
      local[k] = node;
    }
    fm.tets.push_back(local);
    fm.tet_to_mesh_tet.push_back(t);
  }
  if (fm.tets.empty()) throw std::invalid_argument("build_fluid_mesh: the mesh has no fluid tet (label 1)");

  compute_tet_geometry(fm);
  const int nf = fm.num_tets();

  // Face matching over ALL tets (so that faces shared with a solid tet know the solid's label).
  std::vector<FaceRecord> faces;
  faces.reserve(4 * static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> key{mesh.tets[t][kFaceVertices[k][0]], mesh.tets[t][kFaceVertices[k][1]],
                             mesh.tets[t][kFaceVertices[k][2]]};
      std::sort(key.begin(), key.end());
      faces.push_back({key, t, k});
    }
  // Keys are distinct (face, tet) pairs, so the order is total and the parallel sort deterministic.
  tbb::parallel_sort(faces.begin(), faces.end(), [](const FaceRecord& a, const FaceRecord& b) {
    return a.key != b.key ? a.key < b.key : a.mesh_tet < b.mesh_tet;
  });
  fm.neighbor.assign(nf, {-1, -1, -1, -1});
  auto add_boundary = [&](const FaceRecord& f, int other_label) {
    const int t = mesh_tet_to_fluid[f.mesh_tet];
    BoundaryFace bf;
    bf.tet = t;
    bf.local_face = f.local_face;
    for (int a = 0; a < 3; ++a) bf.nodes[a] = fm.tets[t][kFaceVertices[f.local_face][a]];
    set_face_geometry(fm.nodes, bf);
    bf.other_subdomain = other_label;
    fm.boundary_faces.push_back(bf);
  };
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i > 2)
      throw std::invalid_argument("build_fluid_mesh: face shared by more than two tets (non-manifold mesh)");
    if (j - i == 2) {
      const FaceRecord& a = faces[i];
      const FaceRecord& b = faces[i + 1];
      const int fa = mesh_tet_to_fluid[a.mesh_tet], fb = mesh_tet_to_fluid[b.mesh_tet];
      if (fa >= 0 && fb >= 0) {
        fm.neighbor[fa][a.local_face] = fb;
        fm.neighbor[fb][b.local_face] = fa;
      } else if (fa >= 0) {
        add_boundary(a, mesh.subdomain[b.mesh_tet]);
      } else if (fb >= 0) {
        add_boundary(b, mesh.subdomain[a.mesh_tet]);
      }
    } else if (mesh_tet_to_fluid[faces[i].mesh_tet] >= 0) {
      add_boundary(faces[i], 0);
    }
    i = j;
  }

  fm.node_tets.assign(fm.num_nodes(), {});
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 4; ++k) fm.node_tets[fm.tets[t][k]].push_back(t);
  compute_dual_volumes(fm);
  return fm;
}

void update_fluid_mesh_geometry(const mesh::TetMesh& mesh, FluidMesh& fm) {
  for (int i = 0; i < fm.num_nodes(); ++i) fm.nodes[i] = mesh.vertices[fm.node_to_mesh_vertex[i]];
  compute_tet_geometry(fm);
  for (BoundaryFace& f : fm.boundary_faces) set_face_geometry(fm.nodes, f);
  compute_dual_volumes(fm);
}

std::vector<Eigen::Vector3d> moved_nodes(const mesh::TetMesh& mesh, const FluidMesh& fm) {
  std::vector<Eigen::Vector3d> nodes(fm.num_nodes());
  for (int i = 0; i < fm.num_nodes(); ++i) nodes[i] = mesh.vertices[fm.node_to_mesh_vertex[i]];
  return nodes;
}

void update_fluid_mesh_geometry(std::vector<Eigen::Vector3d> nodes, FluidMesh& fm) {
  if (nodes.size() != fm.nodes.size())
    throw std::invalid_argument("fluid mesh: " + std::to_string(nodes.size()) + " node positions for " +
                                std::to_string(fm.nodes.size()) + " nodes");
  fm.nodes = std::move(nodes);
  compute_tet_geometry(fm);
  for (BoundaryFace& f : fm.boundary_faces) set_face_geometry(fm.nodes, f);
  compute_dual_volumes(fm);
}

std::vector<int> matching_tets(const FluidMesh& from, const FluidMesh& to) {
  if (from.num_tets() != to.num_tets()) return {};
  std::vector<int> match(to.num_tets());
  if (from.tet_to_mesh_tet == to.tet_to_mesh_tet && from.tets == to.tets && from.node_to_mesh_vertex == to.node_to_mesh_vertex) {
    std::iota(match.begin(), match.end(), 0);
    return match;
  }
  int num_mesh_tets = 0;
  for (const int t : from.tet_to_mesh_tet) num_mesh_tets = std::max(num_mesh_tets, t + 1);
  std::vector<int> from_tet(num_mesh_tets, -1);
  for (int t = 0; t < from.num_tets(); ++t) from_tet[from.tet_to_mesh_tet[t]] = t;
  for (int t = 0; t < to.num_tets(); ++t) {
    const int mesh_tet = to.tet_to_mesh_tet[t];
    const int u = mesh_tet < num_mesh_tets ? from_tet[mesh_tet] : -1;
    if (u < 0) return {};
    for (int k = 0; k < 4; ++k)
      if (from.node_to_mesh_vertex[from.tets[u][k]] != to.node_to_mesh_vertex[to.tets[t][k]]) return {};
    match[t] = u;
  }
  return match;
}

}  // namespace tetfsi::fluid
