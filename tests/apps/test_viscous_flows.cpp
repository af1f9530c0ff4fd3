// Viscous fluids through `tetfsi run` (fluid/viscosity/, issue 22), at resolutions that run in
// seconds; scripts/bench_viscous.py runs the same scenes at three finer resolutions.
//  - data/scenes/lid_driven_cavity.json (Re = 100, 2D slab with slip faces), edge 0.05 m: the
//    centre-line velocities at 11 of Ghia, Ghia & Shin's (1982) points within 0.08 of the lid speed
//    at t = 10 s (measured: largest 0.066, at y = 0.9531);
//  - data/scenes/stokes_settling.json (coupled, eq. 7), edge 0.015 m at the sphere: the settling
//    speed within 15% of Stokes' with Haberman & Sayre's wall factor, 3.25 cm/s (measured 2.83 cm/s
//    at t = 0.4 s), and the fluid's force on the sphere (pressure + viscous) balancing its weight
//    within 10% once it settles;
//  - a moving wall whose velocity crosses it is refused (exit 2, naming the key) by validate and run.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

/// `tetfsi run` of `scene` (written to a temporary folder named `name`): exit status, log and the
/// probes.csv and stats.csv it wrote.
struct SceneRun {
  SceneRun(const std::string& name, const json& scene) : dir(name) {
    const fs::path file = dir.path() / "scene.json", out = dir.path() / "out";
    std::ofstream(file) << scene.dump(2);
    log = tetfsi_cmd("run " + file.string() + " --out " + out.string() + " --quiet --threads 2", &status);
    if (status == 0) {
      probes = read_csv(out / "probes.csv");
      stats = read_csv(out / "stats.csv");
    }
  }
  TempDir dir;
  int status = -1;
  std::string log;
  Csv probes, stats;
};

}  // namespace

TEST(ViscousFlow, LidDrivenCavityCentreLinesNearGhia) {
  json scene = committed("lid_driven_cavity.json");
  scene["mesh"]["edge_length"] = 0.05;
  scene["simulation"]["end_time"] = 10.0;
  const SceneRun run("viscous_cavity", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const Csv& probes = run.probes;
  // Ghia, Ghia & Shin (1982), Tables I and II, Re = 100.
  const std::vector<std::pair<std::string, double>> ghia = {
      {"u_y0_1719", -0.10150}, {"u_y0_2813", -0.15662}, {"u_y0_4531", -0.21090}, {"u_y0_6172", -0.13641},
      {"u_y0_8516", 0.23151},  {"u_y0_9531", 0.68717},  {"v_x0_0938", 0.12317},  {"v_x0_2344", 0.17527},
      {"v_x0_5000", 0.05454},  {"v_x0_8047", -0.24533}, {"v_x0_9063", -0.16914}};
  const std::size_t last = probes.rows.size() - 1;
  double worst = 0;
  for (const auto& [name, reference] : ghia) {
    const double e = std::abs(probes.at(last, name) - reference);
    worst = std::max(worst, e);
    EXPECT_LE(e, 0.08) << name << " = " << probes.at(last, name) << ", Ghia " << reference;
  }
  std::printf("lid-driven cavity, edge 0.05 m: largest |u - u_Ghia| / U = %.4f\n", worst);
  EXPECT_GT(run.stats.at(run.stats.rows.size() - 1, "viscous_iterations"), 0);
}

TEST(ViscousFlow, SphereSettlesNearStokesTerminalVelocity) {
  json scene = committed("stokes_settling.json");
  scene["simulation"]["end_time"] = 0.4;
  const SceneRun run("viscous_settling", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const Csv& probes = run.probes;
  const double R = 0.05, rho_s = 2000, rho_f = 1000, mu = 100, g = 9.81, wall_factor = 1.68;
  const double stokes = 2.0 / 9.0 * (rho_s - rho_f) * g * R * R / mu / wall_factor;
  const std::size_t last = probes.rows.size() - 1;
  const double v = -(probes.at(last, "centre_z") - probes.at(last - 1, "centre_z")) /
                   (probes.at(last, "time") - probes.at(last - 1, "time"));
  std::printf("settling speed %.5f m/s, Stokes with the wall factor %.5f m/s\n", v, stokes);
  EXPECT_NEAR(v, stokes, 0.15 * stokes);
  // Settled: the fluid's force on the sphere carries its weight (the mesh sphere's volume is within
  // 2% of the sphere's).
  const double weight = rho_s * 4.0 / 3.0 * M_PI * R * R * R * g;
  const double lift = probes.at(last, "drag_z") + probes.at(last, "pressure_force_z");
  EXPECT_NEAR(lift, weight, 0.1 * weight);
  EXPECT_GT(probes.at(last, "drag_z"), 0.0);
}

TEST(ViscousFlow, AMovingWallMustMoveInItsPlane) {
  json scene = committed("lid_driven_cavity.json");
  scene["domain"]["moving_walls"][0]["velocity"] = {1, 0.5, 0};
  const TempDir dir("viscous_wall");
  const fs::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string v = tetfsi_cmd("validate " + file.string(), &status);
  EXPECT_EQ(status, 2) << v;
  EXPECT_NE(v.find("/domain/moving_walls/0/velocity"), std::string::npos) << v;
  const std::string r = tetfsi_cmd("run " + file.string() + " --out " + (dir.path() / "out").string(), &status);
  EXPECT_EQ(status, 2) << r;
  EXPECT_NE(r.find("/domain/moving_walls/0/velocity"), std::string::npos) << r;
}
