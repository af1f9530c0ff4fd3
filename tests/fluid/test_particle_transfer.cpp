// Particle <-> mesh transfers (fluid/particles/transfer.hpp) on a jittered Kuhn mesh, random
// particle velocities and affine matrices (round-off bounds):
// - P2G to the nodes keeps linear momentum, sum_i m_i U_i = sum_p m_p v_p, and with APIC angular
//   momentum, sum_i x_i x m_i U_i = sum_p (x_p x m_p v_p + m_p eps : (∇v_p D_p)^T) (Jiang et al. 2015);
// - P2G to the tets keeps linear momentum, sum_t rho V_t v_t = sum_p m_p v_p, where the particles'
//   nodal masses are the mesh's lumped ones (one particle at each centroid); with random particles
//   the difference (their sampling of the tets' mass) is printed;
// - G2P of a constant field gives every particle that velocity (momentum sum_t rho V_t c kept);
// - the gradients are exact for linear fields, so APIC's G2P of an affine field v = A x + b gives
//   v_p = A x_p + b and ∇v_p = A, and its P2G gives back A c_t + b at every centroid;
// - the FLIP share blends the two: r = 0 is PIC, r = 1 adds the change to the old velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/particles/seeding.hpp"
#include "fluid/particles/transfer.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

struct Fixture {
  FluidMesh mesh;
  ParticleSet particles;
};

/// A 6 x 5 x 4 jittered box of Kuhn tets with 6 particles aimed at per tet (zero velocities).
Fixture seeded(bool affine) {
  std::mt19937 rng(7);
  const Eigen::Vector3d lo(0, 0, 0), hi(0.6, 0.5, 0.4);
  Fixture f;
  f.mesh = build_fluid_mesh(testing::jittered(mesh::structured_box(lo, hi, 6, 5, 4), lo, hi, 0.1, 0.1, rng));
  const TetVectors zero(f.mesh.num_tets(), Eigen::Vector3d::Zero());
  add_particles(f.mesh, f.mesh.volume, Eigen::VectorXd(), 6, zero, nullptr, affine, f.particles);
  return f;
}

Eigen::Vector3d random_vector(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1, 1);
  return {d(rng), d(rng), d(rng)};
}

TEST(ParticleTransfer, SeedingFillsEveryTetWithinTheBand) {
  const Fixture f = seeded(false);
  const std::vector<int> first = f.particles.tet_ranges(f.mesh.num_tets());
  for (int t = 0; t < f.mesh.num_tets(); ++t) ASSERT_EQ(first[t + 1] - first[t], 6) << "tet " << t;
  for (int p = 0; p < f.particles.size(); ++p)
    for (int k = 0; k < 4; ++k)
      ASSERT_GT(0.25 + f.mesh.grad[f.particles.tet[p]][k].dot(f.particles.x[p] - f.mesh.centroid(f.particles.tet[p])), 0)
          << "particle " << p << " outside its tet";
}

Eigen::Matrix3d random_matrix(std::mt19937& rng) {
  Eigen::Matrix3d A;
  A << random_vector(rng), random_vector(rng), random_vector(rng);
  return A;
}

/// eps : M^T, the axial vector of M's antisymmetric part times 2: (M_zy - M_yz, M_xz - M_zx, M_yx - M_xy).
Eigen::Vector3d axial(const Eigen::Matrix3d& M) {
  return {M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1)};
}

TEST(ParticleTransfer, ParticlesToNodesKeepLinearAndAngularMomentum) {
  for (bool affine : {false, true}) {
    Fixture f = seeded(affine);
    std::mt19937 rng(3);
    for (auto& v : f.particles.v) v = random_vector(rng);
    for (auto& G : f.particles.grad_v) G = random_matrix(rng);
    const std::vector<double> m = particle_masses(f.particles, f.mesh.volume, 1000);
    Eigen::Vector3d P = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();
    double scale = 0, L_scale = 0;
    for (int p = 0; p < f.particles.size(); ++p) {
      const Eigen::Vector3d& x = f.particles.x[p];
      P += m[p] * f.particles.v[p];
      L += x.cross(m[p] * f.particles.v[p]);
      scale += m[p] * f.particles.v[p].norm();
      L_scale += m[p] * x.norm() * f.particles.v[p].norm();
      if (!affine) continue;
      const int t = f.particles.tet[p];
      Eigen::Matrix3d D = Eigen::Matrix3d::Zero();  // sum_i w_ip (x_i - x_p)(x_i - x_p)^T
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d d = f.mesh.nodes[f.mesh.tets[t][k]] - x;
        D += (0.25 + f.mesh.grad[t][k].dot(x - f.mesh.centroid(t))) * d * d.transpose();
      }
      L += m[p] * axial(f.particles.grad_v[p] * D);
    }
    const NodalMomentum nodal = particles_to_nodes(f.mesh, f.particles, m);
    Eigen::Vector3d P_nodes = Eigen::Vector3d::Zero(), L_nodes = Eigen::Vector3d::Zero();
    for (int i = 0; i < f.mesh.num_nodes(); ++i) {
      P_nodes += nodal.momentum[i];
      L_nodes += f.mesh.nodes[i].cross(nodal.momentum[i]);
    }
    std::printf("P2G to nodes (%s): |dP| / sum m|v| = %.2e, |dL| / sum m|x||v| = %.2e\n", affine ? "APIC" : "FLIP",
                (P_nodes - P).norm() / scale, (L_nodes - L).norm() / L_scale);
    EXPECT_LT((P_nodes - P).norm(), 1e-12 * scale);
    EXPECT_LT((L_nodes - L).norm(), 1e-12 * L_scale);
  }
}

TEST(ParticleTransfer, ParticlesToTetsKeepLinearMomentumWhereTheNodalMassesAreTheMeshs) {
  Fixture f = seeded(false);
  const double rho = 1000;
  // One particle at each centroid: its hat weights are 1/4, so node i gets sum_t rho V_t / 4.
  ParticleSet one;
  std::mt19937 rng(3);
  for (int t = 0; t < f.mesh.num_tets(); ++t) {
    one.x.push_back(f.mesh.centroid(t));
    one.v.push_back(random_vector(rng));
    one.tet.push_back(t);
  }
  for (ParticleSet* ps : {&one, &f.particles}) {
    if (ps == &f.particles)
      for (auto& v : ps->v) v = random_vector(rng);
    const std::vector<double> m = particle_masses(*ps, f.mesh.volume, rho);
    Eigen::Vector3d before = Eigen::Vector3d::Zero(), after = Eigen::Vector3d::Zero();
    double scale = 0;
    for (int p = 0; p < ps->size(); ++p) {
      before += m[p] * ps->v[p];
      scale += m[p] * ps->v[p].norm();
    }
    TetVectors v(f.mesh.num_tets(), Eigen::Vector3d::Zero());
    const std::vector<char> filled = particles_to_tets(f.mesh, *ps, m, v);
    for (int t = 0; t < f.mesh.num_tets(); ++t) {
      ASSERT_TRUE(filled[t]);
      after += rho * f.mesh.volume[t] * v[t];
    }
    std::printf("P2G to tets, %s: |sum m_p v_p - sum rho V_t v_t| / sum m_p |v_p| = %.2e\n",
                ps == &one ? "one particle per centroid" : "6 random particles per tet", (after - before).norm() / scale);
    if (ps == &one) {
      EXPECT_LT((after - before).norm(), 1e-12 * scale);
    }
  }
}

TEST(ParticleTransfer, TetsToParticlesOfAConstantFieldKeepsItsMomentum) {
  for (bool affine : {false, true}) {
    Fixture f = seeded(affine);
    const Eigen::Vector3d c(0.3, -1.2, 0.7);
    const TetVectors v(f.mesh.num_tets(), c);
    // FLIP at r = 0.5 from particles at rest and a mesh that was at rest: PIC gives c, FLIP 0 + (c - 0).
    tets_to_particles(f.mesh, v, TetVectors(f.mesh.num_tets(), Eigen::Vector3d::Zero()), 0.5, nullptr, f.particles);
    const std::vector<double> m = particle_masses(f.particles, f.mesh.volume, 1000);
    Eigen::Vector3d particle_momentum = Eigen::Vector3d::Zero();
    double mesh_mass = 0;
    for (int p = 0; p < f.particles.size(); ++p) {
      EXPECT_LT((f.particles.v[p] - c).norm(), 1e-14);
      particle_momentum += m[p] * f.particles.v[p];
    }
    for (double V : f.mesh.volume) mesh_mass += 1000 * V;
    EXPECT_LT((particle_momentum - mesh_mass * c).norm(), 1e-12 * mesh_mass * c.norm());
  }
}

TEST(ParticleTransfer, ApicCarriesAnAffineFieldExactly) {
  Fixture f = seeded(true);
  Eigen::Matrix3d A;
  A << 0.3, -1.0, 0.2, 1.0, 0.1, -0.4, 0.5, 0.7, -0.4;
  const Eigen::Vector3d b(0.1, 0.2, -0.3);
  TetVectors v(f.mesh.num_tets());
  for (int t = 0; t < f.mesh.num_tets(); ++t) v[t] = A * f.mesh.centroid(t) + b;
  tets_to_particles(f.mesh, v, {}, 0, nullptr, f.particles);
  double velocity_error = 0, gradient_error = 0;
  for (int p = 0; p < f.particles.size(); ++p) {
    velocity_error = std::max(velocity_error, (f.particles.v[p] - (A * f.particles.x[p] + b)).norm());
    gradient_error = std::max(gradient_error, (f.particles.grad_v[p] - A).norm());
  }
  TetVectors back(f.mesh.num_tets(), Eigen::Vector3d::Zero());
  particles_to_tets(f.mesh, f.particles, particle_masses(f.particles, f.mesh.volume, 1000), back);
  double round_trip = 0;
  for (int t = 0; t < f.mesh.num_tets(); ++t) round_trip = std::max(round_trip, (back[t] - v[t]).norm());
  std::printf("APIC, affine field: max |v_p - (A x_p + b)| = %.2e, max |∇v_p - A| = %.2e, round trip %.2e m/s\n",
              velocity_error, gradient_error, round_trip);
  EXPECT_LT(velocity_error, 1e-12);
  EXPECT_LT(gradient_error, 1e-12);
  EXPECT_LT(round_trip, 1e-12);
}

TEST(ParticleTransfer, FlipRatioBlendsPicAndFlip) {
  Fixture f = seeded(false);
  std::mt19937 rng(5);
  for (auto& v : f.particles.v) v = random_vector(rng);
  const ParticleSet old = f.particles;
  TetVectors before(f.mesh.num_tets()), after(f.mesh.num_tets());
  for (int t = 0; t < f.mesh.num_tets(); ++t) {
    before[t] = random_vector(rng);
    after[t] = before[t] + Eigen::Vector3d(0, 0, -0.1);  // a uniform change: gravity over a step
  }
  ParticleSet flip = old, pic = old;
  tets_to_particles(f.mesh, after, before, 1.0, nullptr, flip);
  tets_to_particles(f.mesh, after, before, 0.0, nullptr, pic);
  const TetMatrices G = tet_velocity_gradients(f.mesh, after, nullptr);
  for (int p = 0; p < old.size(); ++p) {
    EXPECT_LT((flip.v[p] - (old.v[p] + Eigen::Vector3d(0, 0, -0.1))).norm(), 1e-14);
    EXPECT_LT((pic.v[p] - reconstructed_velocity(f.mesh, after, G, old.tet[p], old.x[p])).norm(), 1e-14);
  }
}

}  // namespace
}  // namespace tetfsi::fluid
