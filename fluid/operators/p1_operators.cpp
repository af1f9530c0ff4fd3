#include "fluid/operators/p1_operators.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

#include "mesh/column_gather.hpp"

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
                                              double scale, Eigen::SparseMatrix<double>* earlier) {
  // Column by column in parallel, straight into the compressed matrix (mesh/column_gather.hpp):
  // column unknown[i] gathers V_t grad(phi_a).grad(phi_b) over node i's tets in ascending order,
  // which is the order in which a triplet sum in tet order adds them, so each entry is that sum bit
  // for bit (and L_ij = L_ji exactly: the dot product's terms commute). It reads each node's tets
  // close together because build_fluid_mesh numbers tets and nodes along a space-filling curve (on
  // the mesher's order the gather was 3x slower).
  std::vector<int> node_of(m, -1);
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (unknown[i] >= 0) node_of[unknown[i]] = i;
  return mesh::gather_columns(
      m, m,
      [&](int c, const auto& emit) {
        const int i = node_of[c];
        for (const int t : mesh.node_tets[i]) {
          const auto& tet = mesh.tets[t];
          int b = 0;
          while (tet[b] != i) ++b;
          for (int a = 0; a < 4; ++a) {
            const int r = unknown[tet[a]];
            if (r >= 0) emit(r, [&] { return mesh.volume[t] * mesh.grad[t][a].dot(mesh.grad[t][b]); });
          }
        }
      },
      scale, earlier);
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
