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
  const int nt = mesh.num_tets();
  std::vector<Eigen::Triplet<double>> trip(16 * static_cast<size_t>(nt));
  tbb::parallel_for(0, nt, [&](int t) {
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        trip[16 * static_cast<size_t>(t) + 4 * a + b] = Eigen::Triplet<double>(
            mesh.tets[t][a], mesh.tets[t][b], mesh.volume[t] * mesh.grad[t][a].dot(mesh.grad[t][b]));
  });
  Eigen::SparseMatrix<double> l(mesh.num_nodes(), mesh.num_nodes());
  l.setFromTriplets(trip.begin(), trip.end());
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
