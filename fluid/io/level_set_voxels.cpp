#include "fluid/io/level_set_voxels.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include <openvdb/openvdb.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace tetfsi::fluid {
namespace {

/// A voxel centre on a tet face counts as inside with barycentric coordinates down to -this.
constexpr double kInsideTolerance = 1e-10;

/// Tets per chunk of the parallel sampling; fixed, so the chunks do not depend on the threads.
constexpr int kChunk = 256;

bool near_liquid(const std::array<int, 4>& tet, const Eigen::VectorXd& phi, double band) {
  for (int k = 0; k < 4; ++k)
    if (phi[tet[k]] < band) return true;
  return false;
}

/// The voxels whose centres lie in tet t, with phi there (appended to `out`).
void sample_tet(const FluidMesh& mesh, const Eigen::VectorXd& phi, int t, double h, double band, LevelSetVoxels& out) {
  const auto& tet = mesh.tets[t];
  Eigen::Vector3d lo = mesh.nodes[tet[0]], hi = lo;
  for (int k = 1; k < 4; ++k) {
    lo = lo.cwiseMin(mesh.nodes[tet[k]]);
    hi = hi.cwiseMax(mesh.nodes[tet[k]]);
  }
  Eigen::Vector3i first, last;
  for (int a = 0; a < 3; ++a) {
    first[a] = static_cast<int>(std::ceil(lo[a] / h - 1e-9));
    last[a] = static_cast<int>(std::floor(hi[a] / h + 1e-9));
  }
  const auto& x0 = mesh.nodes[tet[0]];
  const auto g = mesh.grad[t];
  for (int k = first.z(); k <= last.z(); ++k)
    for (int j = first.y(); j <= last.y(); ++j)
      for (int i = first.x(); i <= last.x(); ++i) {
        const Eigen::Vector3d x = Eigen::Vector3d(i, j, k) * h;
        // lambda_m = grad(phi_m) . (x - x_0) for m = 1..3 (hat functions vanish at x_0), lambda_0 = 1 - sum.
        const Eigen::Vector3d d = x - x0;
        const double l1 = g[1].dot(d), l2 = g[2].dot(d), l3 = g[3].dot(d), l0 = 1.0 - l1 - l2 - l3;
        if (l0 < -kInsideTolerance || l1 < -kInsideTolerance || l2 < -kInsideTolerance || l3 < -kInsideTolerance)
          continue;
        const double v = l0 * phi[tet[0]] + l1 * phi[tet[1]] + l2 * phi[tet[2]] + l3 * phi[tet[3]];
        out.index.emplace_back(i, j, k);
        out.phi.push_back(static_cast<float>(std::clamp(v, -band, band)));
      }
}

}  // namespace

std::vector<char> tets_near_zero(const FluidMesh& mesh, const Eigen::VectorXd& values, double band, bool walls) {
  if (values.size() != mesh.num_nodes()) throw std::invalid_argument("tets_near_zero: values do not match the mesh");
  std::vector<char> on_boundary(walls ? mesh.num_nodes() : 0, 0);
  for (const BoundaryFace& f : mesh.boundary_faces)
    for (int n : f.nodes)
      if (walls) on_boundary[n] = 1;
  std::vector<char> out(mesh.num_tets(), 0);
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    double lo = values[mesh.tets[t][0]], hi = lo;
    bool boundary = false;
    for (int n : mesh.tets[t]) {
      lo = std::min(lo, values[n]);
      hi = std::max(hi, values[n]);
      boundary = boundary || (walls && on_boundary[n]);
    }
    out[t] = lo < band && (hi > -band || boundary);
  });
  return out;
}

std::vector<char> tets_below(const FluidMesh& mesh, const Eigen::VectorXd& values, double level) {
  if (values.size() != mesh.num_nodes()) throw std::invalid_argument("tets_below: values do not match the mesh");
  std::vector<char> out(mesh.num_tets(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    double hi = values[mesh.tets[t][0]];
    for (int n : mesh.tets[t]) hi = std::max(hi, values[n]);
    out[t] = hi < level;
  }
  return out;
}

std::vector<char> liquid_tets(const FluidMesh& mesh, const Eigen::VectorXd& phi, double band) {
  if (phi.size() != mesh.num_nodes()) throw std::invalid_argument("liquid_tets: phi does not match the mesh");
  std::vector<char> out(mesh.num_tets(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) out[t] = near_liquid(mesh.tets[t], phi, band);
  return out;
}

LevelSetVoxels sample_level_set_voxels(const FluidMesh& mesh, const Eigen::VectorXd& phi, double voxel_size,
                                       double clamp, const std::vector<char>& tets) {
  if (!(voxel_size > 0) || !(clamp > 0))
    throw std::invalid_argument("sample_level_set_voxels: voxel size and clamp must be positive");
  if (phi.size() != mesh.num_nodes() || tets.size() != mesh.tets.size())
    throw std::invalid_argument("sample_level_set_voxels: phi or the tet selection does not match the mesh");
  const int chunks = (mesh.num_tets() + kChunk - 1) / kChunk;
  std::vector<LevelSetVoxels> part(chunks);
  tbb::parallel_for(0, chunks, [&](int c) {
    for (int t = c * kChunk; t < std::min(mesh.num_tets(), (c + 1) * kChunk); ++t)
      if (tets[t]) sample_tet(mesh, phi, t, voxel_size, clamp, part[c]);
  });
  LevelSetVoxels out;
  out.voxel_size = voxel_size;
  std::size_t total = 0;
  for (const auto& p : part) total += p.size();
  out.index.reserve(total);
  out.phi.reserve(total);
  openvdb::MaskTree seen;
  openvdb::tree::ValueAccessor<openvdb::MaskTree> acc(seen);
  for (const auto& p : part)
    for (std::size_t v = 0; v < p.size(); ++v) {
      const openvdb::Coord c(p.index[v].x(), p.index[v].y(), p.index[v].z());
      if (acc.isValueOn(c)) continue;
      acc.setValueOn(c);
      out.index.push_back(p.index[v]);
      out.phi.push_back(p.phi[v]);
    }
  return out;
}

BoundaryTriangles boundary_near_liquid(const FluidMesh& mesh, const Eigen::VectorXd& phi, double band) {
  BoundaryTriangles out;
  std::unordered_map<int, int> vertex;
  for (const BoundaryFace& f : mesh.boundary_faces) {
    if (!(phi[f.nodes[0]] < band || phi[f.nodes[1]] < band || phi[f.nodes[2]] < band)) continue;
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = vertex.emplace(f.nodes[k], static_cast<int>(out.points.size()));
      if (added) out.points.push_back(mesh.nodes[f.nodes[k]]);
      tri[k] = it->second;
    }
    out.triangles.push_back(tri);
    out.normals.push_back(f.normal);
  }
  return out;
}

double cut_tet_edge_length(const FluidMesh& mesh, const Eigen::VectorXd& phi, double fraction) {
  std::vector<double> mean_edge;  // per cut tet
  for (const auto& tet : mesh.tets) {
    int liquid = 0;
    for (int k = 0; k < 4; ++k) liquid += phi[tet[k]] < 0.0;
    if (liquid == 0 || liquid == 4) continue;
    double sum = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) sum += (mesh.nodes[tet[a]] - mesh.nodes[tet[b]]).norm();
    mean_edge.push_back(sum / 6);
  }
  if (mean_edge.empty()) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(std::clamp(fraction, 0.0, 1.0) * double(mean_edge.size() - 1));
  std::nth_element(mean_edge.begin(), mean_edge.begin() + k, mean_edge.end());
  return mean_edge[k];
}

}  // namespace tetfsi::fluid
