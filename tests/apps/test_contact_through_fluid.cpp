// Solids that reach the container's walls through the fluid (coupling.wall_contact): a ball of
// twice the water's density sinks and comes to rest on the floor, one of half its density rises
// and rests against the lid, at h = 1/30 s and 1/120 s, with a film of fluid of the wall gap
// between (half the near-solid edge length as meshed by default). Run through `tetfsi run` on the
// tank of data/scenes/light_ball_in_water.json (ball radius 0.1 m, tank ±0.4 m).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

struct BallRun {
  int status = -1;
  std::string log;   ///< console output
  Csv stats, probes;
  double film = 0;   ///< the wall gap the run used [m] (from run.log)
};

BallRun run_ball(const TempDir& dir, const std::string& name, double density, double dt, double end_time,
                 int max_step_halvings = -1, double initial_speed = 0) {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/light_ball_in_water.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["simulation"]["end_time"] = end_time;
  scene["simulation"]["dt"] = dt;
  scene["simulation"]["frame_rate"] = 30;
  if (max_step_halvings >= 0) scene["simulation"]["max_step_halvings"] = max_step_halvings;
  scene["solids"][0]["material"]["density"] = density;
  // Rubber's own damping (stiffness-proportional, β = 1 ms): without it the stiff ball (E = 1e8
  // Pa) bounces on the floor for most of a second at h = 1/120 s.
  scene["solids"][0]["material"]["rayleigh_beta"] = 1e-3;
  scene["solids"][0]["initial_velocity"] = {0, -initial_speed, 0};
  scene["coupling"].erase("newmark");  // the default, Chentanez et al. 2006's eq. (18) as printed
  scene["export"] = {{"vtu", false}, {"surfaces", "none"}};
  const fs::path file = dir.path() / (name + ".json");
  std::ofstream(file) << scene.dump(2);
  const fs::path out = dir.path() / name;
  BallRun run;
  run.log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() +
                            " --quiet 2>&1",
                        &run.status);
  if (run.status != 0) return run;
  run.stats = read_csv(out / "stats.csv");
  run.probes = read_csv(out / "probes.csv");
  std::ifstream log(out / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  std::smatch m;
  if (std::regex_search(text, m, std::regex("fluid film ([0-9.eE+-]+) m"))) run.film = std::stod(m[1]);
  return run;
}

/// The ball ends at rest touching the wall through the film: its nearest point (centre ± radius)
/// is between 0 and one near-solid edge length (2 × film) from the wall; the total energy never
/// rises above its start; the ball's speed at the end is a small part of its largest.
void expect_rests_on_wall(const BallRun& run, double wall_y, const std::string& what) {
  ASSERT_EQ(run.status, 0) << what << "\n" << run.log;
  ASSERT_GT(run.film, 0) << what;
  const double radius = 0.1;
  const std::size_t last = run.probes.rows.size() - 1;
  const double y = run.probes.at(last, "centre_y");
  const double gap = std::abs(wall_y - y) - radius;
  double e0 = run.stats.at(0, "total_energy"), e_max = e0, kinetic_max = 0;
  for (std::size_t r = 0; r < run.stats.rows.size(); ++r) {
    e_max = std::max(e_max, run.stats.at(r, "total_energy"));
    kinetic_max = std::max(kinetic_max, run.stats.at(r, "solid_kinetic"));
  }
  const double kinetic_end = run.stats.at(run.stats.rows.size() - 1, "solid_kinetic");
  std::printf("%s: gap %.4f m (film %.4f m), E0 %.3g J, max E %.3g J, end E %.3g J, solid kinetic end/max %.2g\n",
              what.c_str(), gap, run.film, e0, e_max, run.stats.at(run.stats.rows.size() - 1, "total_energy"),
              kinetic_end / kinetic_max);
  // The icosphere's nodes are on the sphere, so its lowest node is at centre − radius.
  EXPECT_GE(gap, 0.0) << what;
  EXPECT_LE(gap, 2 * run.film) << what;
  EXPECT_LE(e_max, e0 + 1e-3 * kinetic_max) << what;
  EXPECT_LT(kinetic_end, 0.05 * kinetic_max) << what;
}

}  // namespace

TEST(ContactThroughFluid, HeavyBallSinksAndRestsOnTheFloor) {
  // It lands at about 0.39 s.
  TempDir dir("sink");
  expect_rests_on_wall(run_ball(dir, "h30", 2000, 1.0 / 30, 0.7), -0.4, "heavy ball, h = 1/30 s");
  expect_rests_on_wall(run_ball(dir, "h120", 2000, 1.0 / 120, 1.0), -0.4, "heavy ball, h = 1/120 s");
}

TEST(ContactThroughFluid, LightBallRisesAndRestsAgainstTheLid) {
  TempDir dir("rise");
  expect_rests_on_wall(run_ball(dir, "l30", 500, 1.0 / 30, 0.7), 0.4, "light ball, h = 1/30 s");
  expect_rests_on_wall(run_ball(dir, "l120", 500, 1.0 / 120, 1.0), 0.4, "light ball, h = 1/120 s");
}

TEST(ContactThroughFluid, StepsThatWouldInvertTheFluidAreHalved) {
  // The heavy ball thrown at the floor at 2 m/s, h = 1/30 s: it moves 6.7 cm per step on 5 cm
  // cells, so the second step's motion inverts fluid tets between it and the floor. With halving
  // off the run stops there (exit 1) naming the cause; with the default it halves those steps
  // (stats.csv `substeps` > 1), lands and comes to rest on the floor.
  TempDir dir("halve");
  const BallRun stop = run_ball(dir, "no_halving", 2000, 1.0 / 30, 0.5, 0, 2.0);
  EXPECT_EQ(stop.status, 1) << stop.log;
  EXPECT_NE(stop.log.find("inverts or flattens"), std::string::npos) << stop.log;
  const BallRun halved = run_ball(dir, "halving", 2000, 1.0 / 30, 0.5, -1, 2.0);
  ASSERT_EQ(halved.status, 0) << halved.log;
  double substeps = 0;
  for (std::size_t r = 0; r < halved.stats.rows.size(); ++r) substeps = std::max(substeps, halved.stats.at(r, "substeps"));
  std::printf("most substeps in one step: %g\n", substeps);
  EXPECT_GT(substeps, 1);
  const double y = halved.probes.at(halved.probes.rows.size() - 1, "centre_y");
  EXPECT_GE(0.4 - 0.1 + y, 0.0);
  EXPECT_LE(0.4 - 0.1 + y, 2 * halved.film);
}
