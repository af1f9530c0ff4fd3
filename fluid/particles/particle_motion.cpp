#include "fluid/particles/particle_motion.hpp"

#include <algorithm>
#include <atomic>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace tetfsi::fluid {
namespace {

constexpr int kBlock = 256;  ///< particles per deterministic work block of locate_particles

/// The P1 interpolant of nodal values at a location (clamped barycentric coordinates if outside).
Eigen::Vector3d interpolate(const FluidMesh& mesh, const TetVectors& nodal, const Location& l) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) u += l.bary[k] * nodal[mesh.tets[l.tet][k]];
  return u;
}

Eigen::Vector3d level_set_gradient(const FluidMesh& mesh, const Eigen::VectorXd& phi, int t) {
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) g += phi[mesh.tets[t][k]] * mesh.grad[t][k];
  return g;
}

}  // namespace

double level_set_at(const FluidMesh& mesh, const Eigen::VectorXd& phi, int t, const Eigen::Vector3d& x) {
  const Eigen::Vector3d d = x - mesh.centroid(t);
  double value = 0;
  for (int k = 0; k < 4; ++k) value += phi[mesh.tets[t][k]] * (0.25 + mesh.grad[t][k].dot(d));
  return value;
}

void advect_particles(const FluidMesh& old_mesh, const TetVectors& velocity, const std::vector<double>* weight,
                      const PointLocator& old_locator, double h, ParticleSet& particles) {
  if (static_cast<int>(velocity.size()) != old_mesh.num_tets())
    throw std::invalid_argument("advect_particles: one velocity per tet of the old mesh expected");
  const TetVectors nodal = weighted_node_average(old_mesh, velocity, weight);
  tbb::parallel_for(0, particles.size(), [&](int p) {
    const Eigen::Vector3d x = particles.x[p];
    const Location l0 = old_locator.locate(x, particles.tet[p]);
    const Eigen::Vector3d x_mid = x + 0.5 * h * interpolate(old_mesh, nodal, l0);
    const Location l_mid = old_locator.locate(x_mid, l0.tet);
    particles.x[p] = x + h * interpolate(old_mesh, nodal, l_mid);
    particles.tet[p] = l_mid.tet;
  });
}

int locate_particles(const FluidMesh& new_mesh, const PointLocator& new_locator, const std::vector<int>& old_to_new,
                     ParticleSet& particles) {
  const int n = particles.size();
  std::atomic<int> moved{0};
  tbb::parallel_for(0, (n + kBlock - 1) / kBlock, [&](int b) {
    int hint = -1, block_moved = 0;
    for (int p = b * kBlock; p < std::min(n, (b + 1) * kBlock); ++p) {
      if (!old_to_new.empty()) hint = old_to_new[particles.tet[p]];
      const Location l = new_locator.locate(particles.x[p], hint);
      hint = l.tet;
      particles.tet[p] = l.tet;
      if (l.inside) continue;
      Eigen::Vector3d on_boundary = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) on_boundary += l.bary[k] * new_mesh.nodes[new_mesh.tets[l.tet][k]];
      particles.x[p] = on_boundary + 1e-3 * (new_mesh.centroid(l.tet) - on_boundary);
      ++block_moved;
    }
    moved += block_moved;
  });
  particles.sort_by_tet(new_mesh.num_tets());
  return moved;
}

std::pair<int, int> keep_in_liquid(const FluidMesh& mesh, const PointLocator& locator, const Eigen::VectorXd& phi,
                                   ParticleSet& particles) {
  if (phi.size() != mesh.num_nodes()) throw std::invalid_argument("keep_in_liquid: one phi per node expected");
  const double dx = mesh.mean_edge_length();
  std::vector<char> keep(particles.size(), 1), moved(particles.size(), 0);
  tbb::parallel_for(0, particles.size(), [&](int p) {
    int t = particles.tet[p];
    Eigen::Vector3d x = particles.x[p];
    double value = level_set_at(mesh, phi, t, x);
    if (value < 0) return;
    keep[p] = 0;
    if (value > dx) return;
    for (int attempt = 0; attempt < 3; ++attempt) {
      const Eigen::Vector3d g = level_set_gradient(mesh, phi, t);
      if (!(g.squaredNorm() > 0)) return;
      x -= (value + 0.05 * dx) / g.squaredNorm() * g;
      const Location l = locator.locate(x, t);
      if (!l.inside) return;
      t = l.tet;
      value = level_set_at(mesh, phi, t, x);
      if (value < 0) {
        particles.x[p] = x;
        particles.tet[p] = t;
        keep[p] = moved[p] = 1;
        return;
      }
    }
  });
  int num_moved = 0, deleted = 0;
  for (int p = 0; p < particles.size(); ++p) {
    num_moved += moved[p];
    deleted += !keep[p];
  }
  particles.keep_only(keep);
  particles.sort_by_tet(mesh.num_tets());
  return {num_moved, deleted};
}

}  // namespace tetfsi::fluid
