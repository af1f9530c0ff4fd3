// The filled toy through the command line (data/scenes/filled_toy_ci.json): a water-filled rubber
// ball (sphere_shell, fluid.fill = cavities: the liquid's only boundary is the shell) released
// 1 cm above a floor. Checked against physics:
//  - before it touches the floor the whole toy, liquid included, falls freely: every point's
//    displacement is -g t²/2 (no pressure builds up in a cavity that falls with its shell);
//  - the closed cavity keeps its volume (issue 6: ≤ 0.1% drift over the run), through the
//    coupled solve alone (the fluid_volume probe);
//  - the floor holds the toy: no surface vertex below the floor plane in any written frame;
//  - every coupled solve converged to the scene's tolerance.
#include <gtest/gtest.h>

#include <cmath>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

TEST(FilledToy, FallsFreelyKeepsCavityVolumeAndRestsOnTheFloor) {
  TempDir dir("filled_toy");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + TETFSI_SOURCE_DIR +
                                          "/data/scenes/filled_toy_ci.json --out " + out.string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv");
  ASSERT_GE(probes.rows.size(), 20u);
  const double g = 9.81, floor_y = -0.31, gap = 0.01;  // the scene's gravity, floor, and rest gap
  const double v0 = probes.at(0, "cavity_volume");
  EXPECT_GT(v0, 0.0);
  double drift = 0, last_t = 0;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    const double t = probes.at(r, "time"), fall = 0.5 * g * t * t;
    drift = std::max(drift, std::abs(probes.at(r, "cavity_volume") / v0 - 1));
    if (fall < 0.9 * gap) {  // free fall, well before the bottom can reach the floor
      EXPECT_NEAR(probes.at(r, "top_y"), -fall, 1e-9 + 1e-6 * fall) << "t = " << t;
      EXPECT_NEAR(probes.at(r, "bottom_y"), -fall, 1e-9 + 1e-6 * fall) << "t = " << t;
    }
    last_t = t;
  }
  std::printf("filled toy CI: cavity volume drift %.2e over %.3f s; bottom %.5f m, top %.5f m at the end\n", drift,
              last_t, probes.at(probes.rows.size() - 1, "bottom_y"), probes.at(probes.rows.size() - 1, "top_y"));
  EXPECT_LE(drift, 1e-3);
  ASSERT_GT(0.5 * g * last_t * last_t, 2 * gap);  // the run does reach the floor
  // The bottom stopped at the floor while the top kept coming down (the toy is squashed).
  const std::size_t last = probes.rows.size() - 1;
  EXPECT_GT(probes.at(last, "bottom_y"), -2 * gap);
  EXPECT_LT(probes.at(last, "top_y"), probes.at(last, "bottom_y") - gap);

  const Csv stats = read_csv(out / "stats.csv");
  for (std::size_t r = 0; r < stats.rows.size(); ++r) EXPECT_LE(stats.at(r, "solver_residual"), 1e-8);
  int frames = 0;
  for (const auto& entry : fs::directory_iterator(out / "surfaces")) {
    const PlyData ply = read_ply(entry.path());
    double lowest = 1e300;
    for (const auto& x : ply.positions) lowest = std::min(lowest, x.y());
    EXPECT_GE(lowest, floor_y - 1e-6) << entry.path();  // PLY positions are 32-bit floats
    ++frames;
  }
  EXPECT_GE(frames, 5);
}
