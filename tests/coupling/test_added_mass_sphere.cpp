// A stiff sphere on springs in a large fluid box (added mass ½ρ_f V, Lamb 1932, §92): the simultaneous system
// oscillates at f = (1/2π)√(k/(m + ½ρ_f V)), the added mass of a sphere in unbounded fluid.
// CI size: a coarse graded CGAL mesh; the finer level is in apps/bench/coupling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "apps/fixtures/sphere_fixture.hpp"

using namespace tetfsi;

TEST(AddedMassSphere, OscillatesAtHalfDisplacedMassCoarse) {
  const test::SphereRun run = test::run_sphere(0.025, 0.15, 2.6);
  std::printf("sphere on springs: %d tets, f = %.5f Hz, exact %.5f Hz, rel. error %.2e\n", run.tets, run.frequency,
              run.exact, run.frequency / run.exact - 1);
  // Coarse CI mesh (a few thousand tets): within 5%; apps/bench/coupling measures finer levels.
  // Seen at this mesh: +3.9% with the default tet-linear advection, +0.9% with BFECC, -2.4% with
  // semi-Lagrangian (the velocity transfer onto the moved mesh), +1.8% expected from the
  // projection's own added-mass error here (fluid/README.md: -10.7% at h/a = 0.24).
  EXPECT_NEAR(run.frequency, run.exact, 0.05 * run.exact);
}
