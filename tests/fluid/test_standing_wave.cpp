// Standing wave in a rectangular tank (free-surface acceptance): the first sloshing mode must
// oscillate at the linear-theory frequency omega^2 = g k tanh(k H) (apps/bench/fluid/
// standing_wave.hpp). The period error converges at first order (measured +5.4%, +2.6%, +1.4% at
// 16, 32 and 64 cells per tank length: bench_fluid --standing-wave); at 32 cells (9.2k tets, 90
// steps) it must be within 3% of theory, and the amplitude must decay by less than 10% per period.
// On APIC particles the amplitude must decay at most a third as fast as with the mesh advection.
#include <gtest/gtest.h>

#include <cmath>

#include "apps/bench/fluid/standing_wave.hpp"

namespace tetfsi::fluid {
namespace {

TEST(FreeSurface, StandingWaveOscillatesAtTheLinearTheoryFrequency) {
  const bench::StandingWaveResult r = bench::standing_wave(32);
  std::printf("standing wave, 32 cells (%d tets, %d steps): period %.5f s against %.5f s (%.2f%%), decay per "
              "period %.3f, max volume drift per step %.2e, max divergence %.2e 1/s\n",
              r.tets, r.steps, r.period, r.period_theory, 100 * (r.period / r.period_theory - 1), r.decay_per_period,
              r.max_volume_drift, r.max_divergence);
  EXPECT_NEAR(r.period / r.period_theory, 1.0, 0.03);
  EXPECT_LT(r.decay_per_period, 0.1);
  EXPECT_LT(r.max_divergence, 1e-7);
}

// The same wave with the velocity on APIC particles (fluid/particles/): carrying the velocity on
// particles removes the back-trace's interpolation loss, so the amplitude must decay at most a third
// as fast as with the mesh advection (tet-linear). Measured at 9.2k tets: 0.55% against 3.10% per
// period. The damping bar of 0.5% per period that issue 41 asks for is missed by this figure since
// the cut tets take the mean of their two splits (-0.39% before); fluid/README.md, "Particles",
// has the longer runs. The period's error is the discretization's, the same with either (within 3%).
TEST(FreeSurface, StandingWaveOnApicParticlesDecaysAThirdAsFastAsOnTheMesh) {
  bench::StandingWaveResult r[2];
  for (int k = 0; k < 2; ++k) {
    bench::StandingWaveSetup setup;
    setup.particles.transfer = k == 0 ? ParticleTransfer::kNone : ParticleTransfer::kApic;
    r[k] = bench::standing_wave(setup);
    std::printf("%s: period %+.2f%%, amplitude decay %.2f%%/period, energy loss %.2f%%/period, %d particles\n",
                k == 0 ? "tet-linear" : "APIC", 100 * (r[k].period / r[k].period_theory - 1),
                100 * r[k].decay_per_period, 100 * r[k].energy_loss_per_period, r[k].particles);
  }
  EXPECT_LT(std::abs(r[1].decay_per_period), r[0].decay_per_period / 3.0);
  EXPECT_NEAR(r[1].period / r[1].period_theory, 1.0, 0.03);
  EXPECT_LT(r[1].max_divergence, 1e-7);
}

}  // namespace
}  // namespace tetfsi::fluid
