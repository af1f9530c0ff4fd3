// Flows carried on particles (FluidParams::particles; fluid/particles/):
// - a liquid ball in free flight (no gravity) keeps its uniform velocity exactly on every tet and
//   particle, and its particles stay strictly inside the liquid and their tets;
// - a rigid rotation keeps its angular momentum to round-off through 64 cycles of APIC's transfers
//   (G2P, P2G) with particles at new random points each cycle, and loses it through PIC's;
// - the particles of a sloshing tank stay in the liquid and in the band of reseeding, and the run
//   is bit for bit the same on one thread and on two.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <tbb/global_control.h>

#include "apps/bench/fluid/standing_wave.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid/particles/particle_motion.hpp"
#include "fluid/particles/seeding.hpp"
#include "fluid/particles/transfer.hpp"
#include "mesh/structured_box.hpp"

namespace tetfsi::fluid {
namespace {

ParticleOptions particles(ParticleTransfer transfer) {
  ParticleOptions o;
  o.transfer = transfer;
  return o;
}

/// Every particle strictly inside its tet and (liquids) strictly inside the liquid.
void expect_confined(const FluidSolver& solver) {
  const ParticleSet& ps = *solver.particles();
  const FluidMesh& m = solver.mesh();
  for (int p = 0; p < ps.size(); ++p) {
    const int t = ps.tet[p];
    for (int k = 0; k < 4; ++k)
      ASSERT_GT(0.25 + m.grad[t][k].dot(ps.x[p] - m.centroid(t)), -1e-12) << "particle " << p << " outside its tet";
    if (solver.has_free_surface()) {
      ASSERT_LT(level_set_at(m, solver.level_set(), t, ps.x[p]), 0.0) << "particle " << p;
    }
  }
}

TEST(ParticleFlows, LiquidBallInFreeFlightKeepsItsVelocity) {
  for (ParticleTransfer transfer : {ParticleTransfer::kApic, ParticleTransfer::kFlip}) {
    const mesh::TetMesh m = mesh::structured_box({0, 0, 0}, {1.0, 0.5, 0.5}, 20, 10, 10);
    FluidParams params;
    params.density = 1000;
    params.apply_gravity = false;
    params.solver.tolerance = 1e-12;
    params.particles = particles(transfer);
    FluidSolver solver(params);
    const Eigen::Vector3d U(0.5, 0.1, 0);
    FluidFields fields;
    fields.velocity.assign(m.num_tets(), U);
    solver.initialize(m, fields);
    LiquidOptions liquid;
    liquid.band = 0.2;
    const Eigen::Vector3d c(0.3, 0.25, 0.25);
    solver.set_liquid(sample_level_set(solver.mesh(), [&](const Eigen::Vector3d& x) { return (x - c).norm() - 0.15; }),
                      liquid);
    const double volume = solver.target_liquid_volume();
    StepReport rep;
    for (int s = 0; s < 20; ++s) rep = solver.step(m, {}, 0.04);
    double worst = 0, worst_particle = 0;
    for (int t = 0; t < solver.mesh().num_tets(); ++t)
      if (solver.liquid().liquid_volume[t] > 0) worst = std::max(worst, (solver.fields().velocity[t] - U).norm());
    if (solver.particles()) for (const Eigen::Vector3d& v : solver.particles()->v) worst_particle = std::max(worst_particle, (v - U).norm());
    std::printf("%s: %d particles, max |v_t - U| %.2e, max |v_p - U| %.2e m/s, volume %.3e of %.3e m^3\n",
                transfer == ParticleTransfer::kApic ? "APIC" : "FLIP", rep.num_particles, worst, worst_particle,
                rep.liquid_volume, volume);
    EXPECT_GT(rep.num_particles, 1000);
    EXPECT_LT(worst, 1e-10);
    EXPECT_LT(worst_particle, 1e-10);
    EXPECT_NEAR(rep.liquid_volume, volume, 1e-9 * volume);
    expect_confined(solver);
  }
}

/// Angular momentum of the tet velocities about the z axis through (0.3, 0.25), sum_t rho V_t (r x v)_z.
double angular_momentum(const FluidMesh& mesh, const TetVectors& v) {
  double L = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector3d r = mesh.centroid(t) - Eigen::Vector3d(0.3, 0.25, 0);
    L += 1000 * mesh.volume[t] * (r.x() * v[t].y() - r.y() * v[t].x());
  }
  return L;
}

/// L after 64 transfer cycles / L before: each cycle reseeds 6 particles per tet at new random
/// points (particles that moved), G2P then P2G, with no grid step between.
double rotation_kept_by_transfers(ParticleTransfer transfer) {
  const mesh::TetMesh m = mesh::structured_box({0, 0, 0}, {0.6, 0.5, 0.2}, 12, 10, 4);
  const FluidMesh mesh = build_fluid_mesh(m);
  TetVectors v(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const Eigen::Vector3d r = mesh.centroid(t) - Eigen::Vector3d(0.3, 0.25, 0);
    v[t] = Eigen::Vector3d(-r.y(), r.x(), 0);
  }
  const double L0 = angular_momentum(mesh, v);
  const bool affine = transfer == ParticleTransfer::kApic;
  for (int cycle = 0; cycle < 64; ++cycle) {
    ParticleSet ps;
    ps.seed_count = static_cast<std::uint64_t>(cycle);
    add_particles(mesh, mesh.volume, Eigen::VectorXd(), 6, v, nullptr, affine, ps);
    tets_to_particles(mesh, v, v, 0.0, nullptr, ps);  // APIC, or PIC (FLIP share 0)
    particles_to_tets(mesh, ps, particle_masses(ps, mesh.volume, 1000), v);
  }
  return angular_momentum(mesh, v) / L0;
}

TEST(ParticleFlows, RigidRotationKeepsItsAngularMomentumThroughApicTransfers) {
  const double apic = rotation_kept_by_transfers(ParticleTransfer::kApic);
  const double pic = rotation_kept_by_transfers(ParticleTransfer::kFlip);
  std::printf("rigid rotation, angular momentum after 64 transfer cycles: APIC %.15f, PIC %.6f\n", apic, pic);
  EXPECT_NEAR(apic, 1.0, 1e-12);  // a rigid rotation is affine: APIC carries it exactly
  EXPECT_LT(pic, apic);
}

/// The sloshing tank of bench_fluid --sloshing, 16 cells along its length, 40 steps.
bench::StandingWaveSetup small_tank(ParticleTransfer transfer) {
  bench::StandingWaveSetup s;
  s.length = 0.8;
  s.width = 0.1;
  s.depth = 0.3;
  s.cells = 16;
  s.periods = 1;
  s.particles = particles(transfer);
  return s;
}

TEST(ParticleFlows, SloshingParticlesStayInTheLiquidAndInTheBand) {
  for (ParticleTransfer transfer : {ParticleTransfer::kApic, ParticleTransfer::kFlip}) {
    bench::StandingWaveSetup setup = small_tank(transfer);
    int steps = 0;
    setup.after_step = [&](const FluidSolver& solver) {
      ++steps;
      expect_confined(solver);
      const std::vector<int> first = solver.particles()->tet_ranges(solver.mesh().num_tets());
      for (int t = 0; t < solver.mesh().num_tets(); ++t)
        if (solver.liquid().liquid_volume[t] >= solver.mesh().volume[t]) {  // full of liquid: 4 to 8
          ASSERT_GE(first[t + 1] - first[t], 4) << "tet " << t;
          ASSERT_LE(first[t + 1] - first[t], 8) << "tet " << t;
        }
    };
    bench::standing_wave(setup);
    EXPECT_EQ(steps, 40);
  }
}

TEST(ParticleFlows, SloshingParticlesRepeatBitForBitOnAnyThreadCount) {
  for (ParticleTransfer transfer : {ParticleTransfer::kApic, ParticleTransfer::kFlip}) {
    bench::StandingWaveResult one, two;
    {
      tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
      one = bench::standing_wave(small_tank(transfer));
    }
    {
      tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
      two = bench::standing_wave(small_tank(transfer));
    }
    ASSERT_EQ(one.energy.size(), two.energy.size());
    for (std::size_t s = 0; s < one.energy.size(); ++s) {
      EXPECT_EQ(one.energy[s], two.energy[s]) << "step " << s;
      EXPECT_EQ(one.amplitude[s], two.amplitude[s]) << "step " << s;
    }
    EXPECT_EQ(one.particles, two.particles);
  }
}

}  // namespace
}  // namespace tetfsi::fluid
