#include "fluid/particles/seeding.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <tbb/parallel_for.h>

#include "fluid/particles/particle_motion.hpp"

namespace tetfsi::fluid {
namespace {

/// SplitMix64 (Steele, Lea & Flood 2014): a counter-based generator, one 64-bit hash per number.
std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Uniform on (0, 1] from a key.
double uniform(std::uint64_t key) { return (static_cast<double>(splitmix64(key) >> 11) + 1.0) * 0x1.0p-53; }

/// The band of file doc for liquid fraction f: {lower, target, upper}.
struct Band {
  int lower, target, upper;
};
Band band(int per_tet, double f) {
  f = std::clamp(f, 0.0, 1.0);
  return {static_cast<int>(std::floor(2.0 * per_tet * f / 3.0 + 0.5)), static_cast<int>(std::floor(per_tet * f + 0.5)),
          static_cast<int>(std::ceil(4.0 * per_tet * f / 3.0))};
}

double fraction(const FluidMesh& mesh, const std::vector<double>& liquid_volume, int t) {
  return liquid_volume[t] / mesh.volume[t];
}

}  // namespace

int delete_crowded_particles(const FluidMesh& mesh, const std::vector<double>& liquid_volume, int per_tet,
                             ParticleSet& particles) {
  const std::vector<int> first = particles.tet_ranges(mesh.num_tets());
  std::vector<char> keep(particles.size(), 1);
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    const int upper = band(per_tet, fraction(mesh, liquid_volume, t)).upper;
    int n = first[t + 1] - first[t];
    while (n > upper) {
      // The particle nearest another (the later one of the closest pair) goes.
      double closest = std::numeric_limits<double>::infinity();
      int worst = -1;
      for (int p = first[t]; p < first[t + 1]; ++p) {
        if (!keep[p]) continue;
        for (int q = first[t]; q < p; ++q)
          if (keep[q] && (particles.x[p] - particles.x[q]).squaredNorm() <= closest) {
            closest = (particles.x[p] - particles.x[q]).squaredNorm();
            worst = p;
          }
      }
      keep[worst] = 0;
      --n;
    }
  });
  const int before = particles.size();
  particles.keep_only(keep);
  return before - particles.size();
}

int add_particles(const FluidMesh& mesh, const std::vector<double>& liquid_volume, const Eigen::VectorXd& phi,
                  int per_tet, const TetVectors& v, const std::vector<char>* valid, bool affine,
                  ParticleSet& particles) {
  const std::vector<int> first = particles.tet_ranges(mesh.num_tets());
  const std::uint64_t key = splitmix64(particles.seed_count);
  const bool first_seeding = particles.size() == 0;
  std::vector<std::vector<Eigen::Vector3d>> added(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    const Band b = band(per_tet, fraction(mesh, liquid_volume, t));
    const int have = first[t + 1] - first[t];
    if (have >= b.target || (!first_seeding && have >= b.lower)) return;
    const std::uint64_t tet_key = splitmix64(key ^ static_cast<std::uint64_t>(t));
    const int wanted = b.target - have;
    for (int attempt = 0; attempt < 8 * b.target && static_cast<int>(added[t].size()) < wanted; ++attempt) {
      Eigen::Vector4d lambda;
      for (int k = 0; k < 4; ++k) lambda[k] = -std::log(uniform(tet_key + 4 * static_cast<std::uint64_t>(attempt) + k));
      lambda /= lambda.sum();
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int k = 0; k < 4; ++k) x += lambda[k] * mesh.nodes[mesh.tets[t][k]];
      if (phi.size() > 0 && !(level_set_at(mesh, phi, t, x) < 0)) continue;
      added[t].push_back(x);
    }
  });
  int count = 0;
  for (const auto& a : added) count += static_cast<int>(a.size());
  const std::vector<Eigen::Vector3d> centroids = count > 0 ? tet_centroids(mesh) : std::vector<Eigen::Vector3d>();
  std::vector<Eigen::Matrix3d> G(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    if (!added[t].empty()) G[t] = tet_velocity_gradient(mesh, centroids, v, valid, t);
  });
  particles.x.reserve(particles.size() + count);
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (const Eigen::Vector3d& x : added[t]) {
      particles.x.push_back(x);
      particles.v.push_back(v[t] + G[t] * (x - centroids[t]));
      if (affine) particles.grad_v.push_back(G[t]);
      particles.tet.push_back(t);
    }
  ++particles.seed_count;
  particles.sort_by_tet(mesh.num_tets());
  return count;
}

}  // namespace tetfsi::fluid
