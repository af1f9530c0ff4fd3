#include "fluid/operators/p1_operators.hpp"

#include <tbb/parallel_for.h>

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
  // Per tet in parallel into fixed triplet slots (tet order), then one sum: deterministic. A
  // column-by-column gather over node_tets was tried instead (no triplet list): bit for bit the
  // same, but 3x slower on CGAL's meshes, whose node numbering scatters each node's tets in memory.
  const int nt = mesh.num_tets();
  std::vector<Eigen::Triplet<double>> trip(16 * static_cast<std::size_t>(nt), Eigen::Triplet<double>(0, 0, 0.0));
  tbb::parallel_for(0, nt, [&](int t) {
    const auto& tet = mesh.tets[t];
    for (int a = 0; a < 4; ++a) {
      if (unknown[tet[a]] < 0) continue;
      for (int b = 0; b < 4; ++b)
        if (unknown[tet[b]] >= 0)
          trip[16 * static_cast<std::size_t>(t) + 4 * a + b] = Eigen::Triplet<double>(
              unknown[tet[a]], unknown[tet[b]], mesh.volume[t] * mesh.grad[t][a].dot(mesh.grad[t][b]));
    }
  });
  Eigen::SparseMatrix<double> l(m, m);
  if (m > 0) l.setFromTriplets(trip.begin(), trip.end());  // unused slots add 0 to (0, 0), on the diagonal
  if (scale != 1.0) l *= scale;
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
