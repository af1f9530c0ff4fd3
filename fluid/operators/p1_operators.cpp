#include "fluid/operators/p1_operators.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

namespace tetfsi::fluid {

TetVectors gradient(const FluidMesh& mesh, const Eigen::VectorXd& p) {
  TetVectors g(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) s += p[mesh.tets[t][k]] * mesh.grad[t][k];
    g[t] = s;
  });
  return g;
}

Eigen::VectorXd gradient_transpose_volume(const FluidMesh& mesh, const TetVectors& u) {
  // Gather per node over its tets (ascending order) instead of scattering: deterministic in parallel.
  Eigen::VectorXd r(mesh.num_nodes());
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    double s = 0.0;
    for (int t : mesh.node_tets[i]) {
      int k = 0;
      while (mesh.tets[t][k] != i) ++k;
      s += mesh.volume[t] * mesh.grad[t][k].dot(u[t]);
    }
    r[i] = s;
  });
  return r;
}


Eigen::SparseMatrix<double> assemble_laplacian(const FluidMesh& mesh) {
  std::vector<int> every(mesh.num_nodes());
  for (int i = 0; i < mesh.num_nodes(); ++i) every[i] = i;
  return assemble_laplacian(mesh, every, mesh.num_nodes());
}

Eigen::SparseMatrix<double> assemble_laplacian(const FluidMesh& mesh, const std::vector<int>& unknown, int m,
                                              double scale) {
  // Column by column in parallel, straight into the compressed matrix: column unknown[i] gathers
  // V_t grad(phi_a).grad(phi_b) over node i's tets in ascending order, which is the order in which
  // a triplet sum in tet order adds them, so each entry is that sum bit for bit (and L_ij = L_ji
  // exactly: the dot product's terms commute). This needs no triplet list (16 per tet) and no
  // serial sort; it reads each node's tets close together because build_fluid_mesh numbers tets
  // and nodes along a space-filling curve (on the mesher's order the gather was 3x slower).
  std::vector<int> node_of(m, -1);
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (unknown[i] >= 0) node_of[unknown[i]] = i;
  Eigen::SparseMatrix<double> l(m, m);
  if (m == 0) return l;
  // Per thread: slot[r] = position of row r in the column being gathered, -1 if absent (reset
  // after each column), so each of the column's ~100 terms finds its entry in O(1).
  tbb::enumerable_thread_specific<std::vector<int>> slots([m] { return std::vector<int>(m, -1); });
  // One column's entries, rows ascending; with `values` false only the rows (for the counts).
  auto column = [&](int c, std::vector<int>& slot, std::vector<std::pair<int, double>>& entries, bool values) {
    entries.clear();
    const int i = node_of[c];
    for (const int t : mesh.node_tets[i]) {
      const auto& tet = mesh.tets[t];
      int b = 0;
      while (tet[b] != i) ++b;
      for (int a = 0; a < 4; ++a) {
        const int r = unknown[tet[a]];
        if (r < 0) continue;
        if (slot[r] < 0) {
          slot[r] = static_cast<int>(entries.size());
          entries.emplace_back(r, 0.0);
        }
        if (values) entries[slot[r]].second += mesh.volume[t] * mesh.grad[t][a].dot(mesh.grad[t][b]);
      }
    }
    for (const auto& e : entries) slot[e.first] = -1;
    std::sort(entries.begin(), entries.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  };
  std::vector<int> count(m + 1, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, m), [&](const tbb::blocked_range<int>& range) {
    std::vector<int>& slot = slots.local();
    std::vector<std::pair<int, double>> entries;
    for (int c = range.begin(); c < range.end(); ++c) {
      column(c, slot, entries, false);
      count[c + 1] = static_cast<int>(entries.size());
    }
  });
  for (int c = 0; c < m; ++c) count[c + 1] += count[c];
  l.resizeNonZeros(count[m]);
  std::copy(count.begin(), count.end(), l.outerIndexPtr());
  tbb::parallel_for(tbb::blocked_range<int>(0, m), [&](const tbb::blocked_range<int>& range) {
    std::vector<int>& slot = slots.local();
    std::vector<std::pair<int, double>> entries;
    for (int c = range.begin(); c < range.end(); ++c) {
      column(c, slot, entries, true);
      for (std::size_t k = 0; k < entries.size(); ++k) {
        l.innerIndexPtr()[count[c] + k] = entries[k].first;
        l.valuePtr()[count[c] + k] = scale * entries[k].second;
      }
    }
  });
  return l;
}

TetVectors average_to_nodes(const FluidMesh& mesh, const TetVectors& u) { return weighted_node_average(mesh, u); }

Eigen::VectorXd average_to_nodes(const FluidMesh& mesh, const Eigen::VectorXd& s) {
  const std::vector<double> n = weighted_node_average(mesh, std::vector<double>(s.data(), s.data() + s.size()));
  return Eigen::Map<const Eigen::VectorXd>(n.data(), static_cast<Eigen::Index>(n.size()));
}

double kinetic_energy(const FluidMesh& mesh, const TetVectors& u) {
  double e = 0.0;
  for (int t = 0; t < mesh.num_tets(); ++t) e += 0.5 * mesh.volume[t] * u[t].squaredNorm();
  return e;
}

}  // namespace tetfsi::fluid
