/// @file sliver_perturbation.cpp
#include "mesh/sliver_perturbation.hpp"

#include <algorithm>

#include "mesh/incidence.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesh_region.hpp"

namespace tetfsi::mesh {
namespace {

double min_dihedral(const TetMesh& m, int t, const Eigen::Vector3d* moved = nullptr, int vertex = -1) {
  std::array<Eigen::Vector3d, 4> p;
  for (int k = 0; k < 4; ++k) p[k] = m.tets[t][k] == vertex ? *moved : m.vertices[m.tets[t][k]];
  if (signed_volume(p[0], p[1], p[2], p[3]) <= 0.0) return -1.0;  // inverted or flat: never accepted
  const auto a = dihedral_angles_deg(p[0], p[1], p[2], p[3]);
  return *std::min_element(a.begin(), a.end());
}

}  // namespace

SliverPassReport perturb_slivers(TetMesh& mesh, double threshold_deg, int sweeps) {
  const int n = mesh.num_vertices();
  const std::vector<int> kind = vertex_kinds(mesh);
  const VertexIncidence tets_around = vertex_incidence(mesh);
  const std::vector<int>& start = tets_around.start;
  const std::vector<int>& incident = tets_around.element;
  // Smallest dihedral angle over the star of v with v at x.
  const auto star_quality = [&](int v, const Eigen::Vector3d& x) {
    double q = 180.0;
    for (int k = start[v]; k < start[v + 1]; ++k) q = std::min(q, min_dihedral(mesh, incident[k], &x, v));
    return q;
  };
  SliverPassReport report;
  std::vector<int> slivers;
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain[t] == kFluidSubdomain && min_dihedral(mesh, t) < threshold_deg) slivers.push_back(t);
  report.slivers_before = static_cast<int>(slivers.size());
  // After a sweep only the tets around the slivers' vertices can have changed.
  const auto remaining = [&] {
    std::vector<int> out;
    for (int t : slivers)
      for (int v : mesh.tets[t])
        for (int k = start[v]; k < start[v + 1]; ++k) out.push_back(incident[k]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    out.erase(std::remove_if(out.begin(), out.end(),
                             [&](int t) {
                               return mesh.subdomain[t] != kFluidSubdomain || min_dihedral(mesh, t) >= threshold_deg;
                             }),
              out.end());
    return out;
  };
  std::vector<char> moved(n, 0);
  for (int sweep = 0; sweep < sweeps && !slivers.empty(); ++sweep) {
    for (int t : slivers) {
      for (int i = 0; i < 4; ++i) {
        const int v = mesh.tets[t][i];
        if (kind[v] != 0) continue;
        const Eigen::Vector3d x = mesh.vertices[v];
        // Neighbour centroid and local edge length.
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        double length = 0.0;
        int count = 0;
        for (int k = start[v]; k < start[v + 1]; ++k)
          for (int w : mesh.tets[incident[k]])
            if (w != v) {
              centroid += mesh.vertices[w];
              length += (mesh.vertices[w] - x).norm();
              ++count;
            }
        centroid /= count;
        length /= count;
        // Unit normal of the sliver's face opposite v.
        const auto& f = mesh.tets[t];
        const Eigen::Vector3d a = mesh.vertices[f[(i + 1) % 4]], b = mesh.vertices[f[(i + 2) % 4]],
                              c = mesh.vertices[f[(i + 3) % 4]];
        Eigen::Vector3d normal = (b - a).cross(c - a);
        if (normal.norm() == 0.0) continue;
        normal.normalize();
        double best = star_quality(v, x);
        Eigen::Vector3d best_x = x;
        const auto consider = [&](const Eigen::Vector3d& y) {
          const double q = star_quality(v, y);
          if (q > best) {
            best = q;
            best_x = y;
          }
        };
        for (double alpha : {1.0, 0.5, 0.25}) consider(x + alpha * (centroid - x));
        for (double s : {0.05, 0.1, 0.2, 0.3}) {
          consider(x + s * length * normal);
          consider(x - s * length * normal);
        }
        if (best_x != x) {
          mesh.vertices[v] = best_x;
          moved[v] = 1;
        }
      }
    }
    slivers = remaining();
  }
  report.slivers_after = static_cast<int>(slivers.size());
  report.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  return report;
}

}  // namespace tetfsi::mesh
