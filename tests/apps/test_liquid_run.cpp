// `tetfsi run` of a liquid with a free surface (fluid.fill "regions"; fluid/liquid/), end to end:
//  - dam_break_ci.json: the liquid keeps its volume to 1e-9 every step (the level set's volume is
//    restored; the tracking drift before the restoration stays below 1% per step), every
//    projection is divergence-free to 1e-8 U/h, every frame's liquid surface is closed, outward and
//    encloses the liquid volume, no surface vertex lies inside the post, and the front has not run
//    ahead of Ritter's dry-bed bound x0 + 2 sqrt(g H) t (Ritter 1892; the inviscid upper limit);
//  - a nozzle (an emitter over a shallow pool) adds liquid while it is on and the volume then
//    stays: the volume grows by at least the nozzle's own box and is constant after it switches off;
//  - a free surface with a deforming solid is refused by validate and run alike (exit 2, naming
//    the key).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

std::string tetfsi_cmd(const std::string& args, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

json committed(const std::string& name) {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes" / name);
  return json::parse(in);
}

/// Volume enclosed by a closed, outward-oriented triangle surface (divergence theorem) [m^3].
double enclosed_volume(const PlyData& ply) {
  double v = 0;
  for (const auto& t : ply.triangles)
    v += ply.positions[t[0]].dot(ply.positions[t[1]].cross(ply.positions[t[2]])) / 6.0;
  return v;
}

/// Number of edges not shared by exactly two triangles (0 for a closed surface).
int open_edges(const PlyData& ply) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : ply.triangles)
    for (int k = 0; k < 3; ++k) ++count[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  int open = 0;
  for (const auto& [edge, n] : count) open += n != 2;
  return open;
}

}  // namespace

TEST(LiquidRun, DamBreakKeepsItsVolumeAndWritesClosedSurfaces) {
  const json scene = committed("dam_break_ci.json");
  TempDir dir("liquid_dam_break");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log =
      tetfsi_cmd("run " + (fs::path(TETFSI_SOURCE_DIR) / "data/scenes/dam_break_ci.json").string() + " --out " +
                     out.string() + " --quiet --threads 1",
                 &status);
  ASSERT_EQ(status, 0) << log;
  const Csv stats = read_csv(out / "stats.csv"), probes = read_csv(out / "probes.csv");
  ASSERT_GT(stats.rows.size(), 5u);
  const double g = 9.81, H = 0.6, x0 = 0.4, U = std::sqrt(2 * g * H);
  const double h = scene["mesh"]["edge_length_near_solids"].get<double>();
  const double v0 = probes.at(0, "liquid_volume");
  EXPECT_NEAR(v0, 0.4 * 0.6 * 0.4, 0.01 * 0.4 * 0.6 * 0.4);  // the column, as the P1 level set sees it
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_NEAR(stats.at(r, "liquid_volume"), v0, 1e-9 * v0) << "step " << r + 1;
    EXPECT_LT(std::abs(stats.at(r, "volume_drift")), 0.01) << "step " << r + 1;
    EXPECT_LE(stats.at(r, "max_divergence"), 1e-8 * U / h) << "step " << r + 1;
    EXPECT_TRUE(std::isfinite(stats.at(r, "kinetic_energy")));
  }
  // Frames: t = 0, 0.05, ..., 0.3 s.
  const Eigen::Vector3d post_lo(1.04, 0.05, 0.14), post_hi(1.16, 0.35, 0.26);
  double front = 0;
  for (int frame = 0; frame <= 6; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "liquid_%05d.ply", frame);
    const auto ply = read_ply(out / "surfaces" / name);
    ASSERT_FALSE(ply.triangles.empty());
    ASSERT_EQ(ply.velocities.size(), ply.positions.size());
    EXPECT_EQ(open_edges(ply), 0) << "frame " << frame;
    EXPECT_NEAR(enclosed_volume(ply), v0, 1e-5 * v0) << "frame " << frame;  // float coordinates
    const double t = 0.05 * frame;
    front = 0;
    for (const auto& x : ply.positions) {
      front = std::max(front, x.x());
      const bool inside_post = ((x - post_lo).array() > 1e-6).all() && ((post_hi - x).array() > 1e-6).all();
      EXPECT_FALSE(inside_post) << "frame " << frame << ": liquid vertex inside the post";
    }
    EXPECT_LE(front, x0 + 2 * std::sqrt(g * H) * t + h) << "frame " << frame;
  }
  EXPECT_GT(front, x0 + 2 * h);  // the column has collapsed and run out
}

TEST(LiquidRun, FreeSurfaceWithDeformingSolidIsRefused) {
  json scene = committed("dam_break_ci.json");
  scene["solids"][0]["motion"] = {{"type", "none"}};
  TempDir dir("liquid_refused");
  const fs::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump(2);
  int validate_status = -1, run_status = -1;
  const std::string validate = tetfsi_cmd("validate " + file.string(), &validate_status);
  const std::string run = tetfsi_cmd("run " + file.string() + " --out " + (dir.path() / "out").string(), &run_status);
  EXPECT_EQ(validate_status, 2) << validate;
  EXPECT_EQ(run_status, 2) << run;
  EXPECT_NE(validate.find("/solids/0/motion/type"), std::string::npos) << validate;
  EXPECT_NE(run.find("/solids/0/motion/type"), std::string::npos) << run;
}

TEST(LiquidRun, NozzleAddsLiquidWhileOnAndTheVolumeThenStays) {
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.4, "frame_rate": 20, "cfl": 0.8, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [0, 0, 0], "hi": [0.4, 0.4, 0.4]},
    "mesh": {"edge_length": 0.05},
    "fluid": {"type": "liquid", "fill": "regions", "regions": [{"type": "below", "height": 0.06}],
              "solver": {"type": "amg", "tolerance": 1e-8}},
    "emitters": [{"shape": {"type": "box", "lo": [0.125, 0.2, 0.125], "hi": [0.275, 0.3, 0.275]},
                  "velocity": [0, -1, 0], "start_time": 0, "end_time": 0.2}],
    "probes": [{"name": "volume", "kind": "fluid_volume"}]
  })");
  TempDir dir("liquid_nozzle");
  const fs::path file = dir.path() / "scene.json", out = dir.path() / "out";
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string log = tetfsi_cmd("run " + file.string() + " --out " + out.string() + " --quiet --threads 1", &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv");
  const double pool = 0.4 * 0.4 * 0.06, nozzle = 0.15 * 0.1 * 0.15, flux = 1.0 * 0.15 * 0.15;
  EXPECT_NEAR(probes.at(0, "volume"), pool, 0.01 * pool);
  double at_switch_off = 0, last = probes.at(0, "volume");
  for (std::size_t r = 1; r < probes.rows.size(); ++r) {
    const double t = probes.at(r, "time"), v = probes.at(r, "volume");
    if (t <= 0.2 + 1e-9) {
      EXPECT_GE(v, last - 1e-12 * pool) << "t = " << t;  // never loses liquid while pouring
      at_switch_off = v;
    } else {
      EXPECT_NEAR(v, at_switch_off, 1e-9 * at_switch_off) << "t = " << t;
    }
    last = v;
  }
  // The nozzle box itself, then what flowed out of it at about 1 m/s through its 0.0225 m^2 floor
  // for 0.2 s (more than half and less than twice that: gravity speeds the stream up).
  const double added = at_switch_off - probes.at(0, "volume");
  EXPECT_GT(added, nozzle + 0.5 * flux * 0.2);
  EXPECT_LT(added, nozzle + 2.0 * flux * 0.2);
}
