// Added mass of a cylinder in a fixed coaxial cylinder, through `tetfsi run`
// (data/scenes/coaxial_rod_ci.json): a stiff rod of radius a on lateral springs of total stiffness
// k, concentric in a closed cylinder of water of radius b, oscillates transversely at
//   f = (1/2π) √(k / (m + m_a)),  m_a = ρ π a² L (b² + a²)/(b² − a²)
// (potential flow in the annulus, per unit length; Britannica 1911 "Hydromechanics" eq. 14,
// Païdoussis, Fluid–Structure Interactions vol. 1, p. 44). The frequency is measured from the zero
// crossings of the rod centre's transverse displacement in probes.csv.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

/// Frequency [Hz] from the zero crossings of column `x` after t = 0 (linear interpolation between
/// rows): (crossings − 1) half periods between the first and the last.
double crossing_frequency(const Csv& probes, const std::string& x, int* crossings) {
  std::vector<double> at;
  for (std::size_t r = 1; r < probes.rows.size(); ++r) {
    const double x0 = probes.at(r - 1, x), x1 = probes.at(r, x);
    const double t0 = probes.at(r - 1, "time"), t1 = probes.at(r, "time");
    if ((x0 > 0 && x1 <= 0) || (x0 < 0 && x1 >= 0)) at.push_back(t0 + (t1 - t0) * x0 / (x0 - x1));
  }
  *crossings = static_cast<int>(at.size());
  return at.size() < 2 ? 0.0 : (at.size() - 1) / (2 * (at.back() - at.front()));
}

}  // namespace

TEST(CoaxialRod, OscillatesAtTheCoaxialCylinderAddedMassFrequency) {
  const fs::path scene_file = fs::path(TETFSI_SOURCE_DIR) / "data/scenes/coaxial_rod_ci.json";
  const nlohmann::json scene = nlohmann::json::parse(std::ifstream(scene_file));
  const auto& rod = scene["solids"][0];
  const double a = rod["geometry"]["radius"], length = rod["geometry"]["length"];
  const double b = scene["domain"]["container"]["radius"];
  const double rho = scene["fluid"]["density"], rho_s = rod["material"]["density"];
  const double k = rod["springs"][0]["stiffness"];
  const double m = rho_s * M_PI * a * a * length;
  const double m_a = rho * M_PI * a * a * length * (b * b + a * a) / (b * b - a * a);
  const double exact = std::sqrt(k / (m + m_a)) / (2 * M_PI);
  const double vacuum = std::sqrt(k / m) / (2 * M_PI);
  const double unbounded = std::sqrt(k / (m + rho * M_PI * a * a * length)) / (2 * M_PI);  // b → ∞

  TempDir dir("coaxial_rod");
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + scene_file.string() + " --out " +
                                          (dir.path() / "out").string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(dir.path() / "out" / "probes.csv");
  int crossings = 0;
  const double f = crossing_frequency(probes, "centre_x", &crossings);
  std::printf("coaxial rod: f = %.4f Hz, exact %.4f Hz (error %+.2f%%); in vacuum %.4f Hz, unbounded fluid %.4f Hz; "
              "%d zero crossings\n",
              f, exact, 100 * (f / exact - 1), vacuum, unbounded, crossings);
  ASSERT_GE(crossings, 4) << "fewer than two periods in the run";
  // The motion stays transverse: the rod neither slides along its axis nor leaves the x-y plane
  // (an end gap too thin for the mesh couples it to the caps: 10% of the x amplitude at 2.5 mm).
  double x_max = 0, yz_max = 0;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    x_max = std::max(x_max, std::abs(probes.at(r, "centre_x")));
    yz_max = std::max({yz_max, std::abs(probes.at(r, "centre_y")), std::abs(probes.at(r, "centre_z"))});
  }
  EXPECT_LT(yz_max, 0.05 * x_max) << "largest |y|, |z| of the rod centre against its largest |x|";
  // Convergence measured with scripts/bench_coaxial_rod.py (coupling/README.md): the discrete
  // annulus flow under-resolves m_a, so f is high and converges from above, +6.1% at this size
  // (edge a/3 at the rod), +3.6% and +2.9% at a/5 and a/7, +1.9% for the benchmark scene
  // (coaxial_rod.json: a/7, twice as long, half the end effect). The 3% bar is the benchmark's;
  // here the bound keeps the sign and 2 points over the CI figure.
  EXPECT_GT(f, exact);
  EXPECT_LT(f / exact - 1, 0.08);
  // The test can fail: both the in-vacuum frequency (+63%) and the unbounded-fluid one (+15%)
  // lie well outside the bound.
  EXPECT_GT(vacuum / exact - 1, 0.5);
  EXPECT_GT(unbounded / exact - 1, 0.10);
  EXPECT_LT(f, unbounded);
}
