// Standing wave in a rectangular tank (free-surface acceptance): the first sloshing mode must
// oscillate at the linear-theory frequency omega^2 = g k tanh(k H) (apps/bench/fluid/
// standing_wave.hpp). The period error converges at first order (measured +5.4%, +2.6%, +1.4% at
// 16, 32 and 64 cells per tank length: bench_fluid --standing-wave); at 32 cells (9.2k tets, 90
// steps) it must be within 3% of theory, and the amplitude must decay by less than 10% per period.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tetfsi::fluid
