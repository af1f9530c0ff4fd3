// `solids[i].springs` through `tetfsi run` (solid runner): a stiff 1 kg block tied to its rest
// position by springs of total stiffness k oscillates as a mass on a spring, f = (1/2π)√(k/m).
// The trapezoidal scheme lengthens the period by (ωh)²/12 = 5e-5 here; the block's elastic modes
// (E = 1e8 Pa) are far above f, so the tolerance 0.5% covers the discretisation with margin.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

/// Frequency [Hz] of the block's x motion from its upward zero crossings (linear interpolation).
double frequency_of(const Csv& probes) {
  double first = -1, last = -1, prev = 0;
  int crossings = 0;
  for (std::size_t i = 0; i < probes.rows.size(); ++i) {
    const double x = probes.at(i, "c_x"), t = probes.at(i, "time");
    if (i > 0 && prev < 0 && x >= 0) {
      const double tc = t - (t - probes.at(i - 1, "time")) * x / (x - prev);
      if (first < 0) first = tc;
      last = tc;
      ++crossings;
    }
    prev = x;
  }
  return crossings >= 2 ? (crossings - 1) / (last - first) : 0;
}

}  // namespace

TEST(SceneSprings, BlockOnSpringsOscillatesAtSqrtKOverM) {
  TempDir dir("springs");
  const double k = 100, m = 1000 * 0.1 * 0.1 * 0.1;  // total stiffness [N/m], block mass [kg]
  nlohmann::json scene = nlohmann::json::parse(R"({
    "simulation": {"end_time": 2.0, "dt": 0.0025, "frame_rate": 10, "gravity": [0, 0, 0]},
    "mesh": {"edge_length": 0.05},
    "solids": [{"name": "block", "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
                "material": {"density": 1000, "youngs_modulus": 1e8, "poissons_ratio": 0.3},
                "integrator": {"scheme": "trapezoidal"},
                "initial_velocity": [-0.05, 0, 0],
                "springs": [{"name": "all", "region": {"lo": [-1, -1, -1], "hi": [1, 1, 1]}, "stiffness": 100}]}],
    "probes": [{"name": "c", "kind": "point_displacement", "solid": "block", "point": [0, 0, 0]},
               {"name": "energy", "kind": "total_energy"}],
    "export": {"vtu": false, "surfaces": "none"}
  })");
  const fs::path file = dir.path() / "block.json", out = dir.path() / "out";
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string log =
      run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() + " --quiet 2>&1", &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv");
  const double exact = std::sqrt(k / m) / (2 * M_PI), f = frequency_of(probes);
  std::printf("block on springs: f = %.5f Hz, exact %.5f Hz (%+.2e)\n", f, exact, f / exact - 1);
  EXPECT_NEAR(f, exact, 5e-3 * exact);
  // Energy ½ m v0² is kept by the trapezoidal rule (spring energy included in total_energy).
  const double e0 = 0.5 * m * 0.05 * 0.05;
  for (std::size_t i = 1; i < probes.rows.size(); ++i) EXPECT_NEAR(probes.at(i, "energy"), e0, 1e-3 * e0);
}
