#include "fluid/particles/transfer.hpp"

#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <tbb/parallel_for.h>

namespace tetfsi::fluid {

std::vector<Eigen::Vector3d> tet_centroids(const FluidMesh& mesh) {
  std::vector<Eigen::Vector3d> c(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) { c[t] = mesh.centroid(t); });
  return c;
}

namespace {

/// The least-squares gradient over the tets s that `neighbours` visits (calls back with each):
/// G (sum d d^T) = sum (v_s - v_t) d^T in the directions with eigenvalues of sum d d^T above
/// `cutoff` of the largest; false (G = 0) if those are fewer than three.
template <class ForEach>
bool least_squares_gradient(const std::vector<Eigen::Vector3d>& centroids, const TetVectors& v, int t, double cutoff,
                            const ForEach& neighbours, Eigen::Matrix3d& G) {
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero();
  neighbours([&](int s) {
    const Eigen::Vector3d d = centroids[s] - centroids[t];
    N += d * d.transpose();
    B += (v[s] - v[t]) * d.transpose();
  });
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(N);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  G.setZero();
  if (!(lambda[2] > 0.0)) return false;
  Eigen::Vector3d inverse = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (lambda[k] > cutoff * lambda[2]) inverse[k] = 1.0 / lambda[k];
  G = B * eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose();
  return inverse[0] > 0;
}

}  // namespace

Eigen::Matrix3d tet_velocity_gradient(const FluidMesh& mesh, const std::vector<Eigen::Vector3d>& centroids,
                                      const TetVectors& v, const std::vector<char>* valid, int t) {
  auto usable = [&](int s) { return s >= 0 && s != t && (!valid || (*valid)[s]); };
  Eigen::Matrix3d G;
  // The face neighbours first (four tets: cheap); where they do not span 3D well (walls, the
  // surface), the tets sharing a node, counted once per shared node.
  if (least_squares_gradient(centroids, v, t, 1e-2,
                             [&](const auto& add) {
                               for (int s : mesh.neighbor[t])
                                 if (usable(s)) add(s);
                             },
                             G))
    return G;
  // Near a wall or the surface the ring may lie nearly in a plane: the gradient across it is
  // then left at zero.
  least_squares_gradient(centroids, v, t, 1e-6,
                         [&](const auto& add) {
                           for (int node : mesh.tets[t])
                             for (int s : mesh.node_tets[node])
                               if (usable(s)) add(s);
                         },
                         G);
  return G;
}

TetMatrices tet_velocity_gradients(const FluidMesh& mesh, const TetVectors& v, const std::vector<char>* valid) {
  if (static_cast<int>(v.size()) != mesh.num_tets())
    throw std::invalid_argument("tet_velocity_gradients: one velocity per tet expected");
  const std::vector<Eigen::Vector3d> centroids = tet_centroids(mesh);
  TetMatrices G(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) { G[t] = tet_velocity_gradient(mesh, centroids, v, valid, t); });
  return G;
}

std::vector<double> particle_masses(const ParticleSet& particles, const std::vector<double>& liquid_volume,
                                    double density) {
  const std::vector<int> first = particles.tet_ranges(static_cast<int>(liquid_volume.size()));
  std::vector<double> m(particles.size());
  for (int p = 0; p < particles.size(); ++p) {
    const int t = particles.tet[p];
    m[p] = density * liquid_volume[t] / (first[t + 1] - first[t]);
  }
  return m;
}

NodalMomentum particles_to_nodes(const FluidMesh& mesh, const ParticleSet& particles, const std::vector<double>& m) {
  if (static_cast<int>(m.size()) != particles.size())
    throw std::invalid_argument("particles_to_nodes: one mass per particle expected");
  const bool affine = static_cast<int>(particles.grad_v.size()) == particles.size() && particles.size() > 0;
  const std::vector<int> first = particles.tet_ranges(mesh.num_tets());
  NodalMomentum out{std::vector<double>(mesh.num_nodes(), 0.0), TetVectors(mesh.num_nodes(), Eigen::Vector3d::Zero())};
  // Gathered per node (no two threads write one node), over its tets in ascending order.
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    const Eigen::Vector3d& x_i = mesh.nodes[i];
    for (int t : mesh.node_tets[i]) {
      if (first[t] == first[t + 1]) continue;
      int k = 0;
      while (mesh.tets[t][k] != i) ++k;
      const Eigen::Vector3d grad_k = mesh.grad[t][k], c = mesh.centroid(t);
      for (int p = first[t]; p < first[t + 1]; ++p) {
        const double w = m[p] * (0.25 + grad_k.dot(particles.x[p] - c));  // w_ip m_p
        out.mass[i] += w;
        out.momentum[i] += w * (affine ? Eigen::Vector3d(particles.v[p] + particles.grad_v[p] * (x_i - particles.x[p]))
                                       : particles.v[p]);
      }
    }
  });
  return out;
}

std::vector<char> particles_to_tets(const FluidMesh& mesh, const ParticleSet& particles, const std::vector<double>& m,
                                    TetVectors& v) {
  if (static_cast<int>(v.size()) != mesh.num_tets())
    throw std::invalid_argument("particles_to_tets: one velocity per tet expected");
  const NodalMomentum nodal = particles_to_nodes(mesh, particles, m);
  std::vector<char> filled(mesh.num_tets(), 0);
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i : mesh.tets[t]) {
      if (!(nodal.mass[i] > 0)) return;
      sum += nodal.momentum[i] / nodal.mass[i];
    }
    v[t] = 0.25 * sum;
    filled[t] = 1;
  });
  return filled;
}

void tets_to_particles(const FluidMesh& mesh, const TetVectors& v, const TetVectors& transferred, double flip_ratio,
                       const std::vector<char>* valid, ParticleSet& particles) {
  const bool affine = static_cast<int>(particles.grad_v.size()) == particles.size() && particles.size() > 0;
  if (affine) {
    const TetMatrices G = tet_velocity_gradients(mesh, v, valid);
    tbb::parallel_for(0, particles.size(), [&](int p) {
      const int t = particles.tet[p];
      particles.v[p] = reconstructed_velocity(mesh, v, G, t, particles.x[p]);
      particles.grad_v[p] = G[t];
    });
    return;
  }
  if (transferred.size() != v.size()) throw std::invalid_argument("tets_to_particles: v^{P2G} does not match the mesh");
  TetVectors dv(v.size());
  for (std::size_t t = 0; t < v.size(); ++t) dv[t] = v[t] - transferred[t];
  const TetMatrices G_dv = tet_velocity_gradients(mesh, dv, valid);
  const TetMatrices G = flip_ratio < 1.0 ? tet_velocity_gradients(mesh, v, valid) : TetMatrices();
  tbb::parallel_for(0, particles.size(), [&](int p) {
    const int t = particles.tet[p];
    const Eigen::Vector3d flip = particles.v[p] + reconstructed_velocity(mesh, dv, G_dv, t, particles.x[p]);
    particles.v[p] = flip_ratio < 1.0
                         ? Eigen::Vector3d((1.0 - flip_ratio) * reconstructed_velocity(mesh, v, G, t, particles.x[p]) +
                                           flip_ratio * flip)
                         : flip;
  });
}

}  // namespace tetfsi::fluid
