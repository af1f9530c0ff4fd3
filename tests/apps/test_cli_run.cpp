// `tetfsi run` end to end with the kinematic runner (no CGAL needed): frames read back with VTK's
// own reader and an independent PLY reader match what was written and the prescribed rigid
// motion; a run that diverges stops with exit code 1 before writing the bad step and leaves
// earlier frames and other files intact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "apps/run/progress.hpp"
#include "csv.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

std::string tetfsi_run(const fs::path& scene, const fs::path& out, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " run " + scene.string() + " --out " + out.string() +
                         " --quiet 2>&1",
                     status);
}

// A 0.6 x 0.01 x 0.3 m slab spinning at omega = 2 rad/s about the y axis through (0.1, 0, 0).
const char* kSpinning = R"({
  "simulation": {"end_time": 0.4, "dt": 0.02, "frame_rate": 10},
  "solids": [{"name": "sheet", "geometry": {"type": "sheet", "size": [0.6, 0.3], "thickness": 0.01},
              "material": {"density": 500, "youngs_modulus": 1e6, "poissons_ratio": 0.3},
              "motion": {"type": "rotation", "axis": [0, 2, 0], "center": [0.1, 0, 0], "angular_velocity": 2}}],
  "probes": [{"name": "volume", "kind": "solid_volume", "solid": "sheet"}]
})";

}  // namespace

TEST(CliRun, KinematicRunFramesMatchWhatWasWritten) {
  TempDir dir("run");
  const fs::path scene = dir.path() / "spin.json", out = dir.path() / "out";
  std::ofstream(scene) << kSpinning;
  int status = -1;
  const std::string log = tetfsi_run(scene, out, &status);
  ASSERT_EQ(status, 0) << log;

  // VTK reads every frame listed in the .pvd: 8 points, 12 triangles, the two point fields.
  const auto frames = lines(vtk_describe(out / "sheet.pvd", &status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(frames.size(), 5u);  // t = 0, 0.1, 0.2, 0.3, 0.4
  expect_pvd_frames(frames, 0.1, " 8 12 p:velocity:3 p:displacement:3");

  // PLY frames: counts, and the velocity is omega x (x - c) of the written positions.
  const Eigen::Vector3d w(0, 2, 0), c(0.1, 0, 0);
  std::vector<Eigen::Vector3d> first;
  for (int k = 0; k < 5; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "sheet_%05d.ply", k);
    const auto ply = read_ply(out / "surfaces" / name);
    ASSERT_EQ(ply.positions.size(), 8u);
    ASSERT_EQ(ply.triangles.size(), 12u);
    ASSERT_EQ(ply.velocities.size(), 8u);
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d expected = w.cross(ply.positions[i] - c);
      EXPECT_LT((ply.velocities[i] - expected).norm(), 1e-5) << "frame " << k << " vertex " << i;
      // A rotation by 2 rad/s * 0.1 k s about the axis: compare with frame 0 rotated.
      if (k == 0) first.push_back(ply.positions[i]);
      const Eigen::Vector3d rotated = c + Eigen::AngleAxisd(0.2 * k, Eigen::Vector3d::UnitY()) * (first[i] - c);
      EXPECT_LT((ply.positions[i] - rotated).norm(), 1e-6) << "frame " << k << " vertex " << i;
    }
  }

  // stats.csv: one row per step; probes.csv: the enclosed volume stays 0.6 * 0.01 * 0.3 m^3.
  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 20u);
  EXPECT_EQ(stats.header[0], "step");
  EXPECT_NEAR(stats.at(19, "time"), 0.4, 1e-12);
  EXPECT_EQ(stats.at(19, "vertices"), 8);
  EXPECT_NEAR(stats.at(0, "max_speed"), 2 * std::hypot(0.4, 0.15), 1e-9);  // farthest corner
  const Csv probes = read_csv(out / "probes.csv");
  ASSERT_EQ(probes.rows.size(), 21u);
  for (std::size_t r = 0; r < probes.rows.size(); ++r) EXPECT_NEAR(probes.at(r, "volume"), 0.6 * 0.01 * 0.3, 1e-12);

  const std::string runlog = read_text(out / "run.log");
  EXPECT_NE(runlog.find("tetfsi 0."), std::string::npos);
  EXPECT_NE(runlog.find("\"cfl\": 0.5"), std::string::npos) << "the resolved scene (with defaults) is logged";
}

TEST(CliRun, UpAxisZTurnsEveryExportedPositionAndVector) {
  // export.up_axis "z": every written position and vector is the scene's turned by +90 degrees
  // about x, (x, y, z) -> (x, -z, y), exactly; the CSVs are unchanged.
  TempDir dir("up_axis");
  std::map<std::string, fs::path> outs;
  for (const std::string axis : {"y", "z"}) {
    nlohmann::json scene = nlohmann::json::parse(kSpinning);
    scene["export"]["up_axis"] = axis;
    const fs::path file = dir.path() / ("spin_" + axis + ".json");
    std::ofstream(file) << scene.dump(2);
    int status = -1;
    const std::string log = tetfsi_run(file, dir.path() / axis, &status);
    ASSERT_EQ(status, 0) << log;
    outs[axis] = dir.path() / axis;
  }
  const auto turn = [](const Eigen::Vector3d& x) { return Eigen::Vector3d(x.x(), -x.z(), x.y()); };
  const auto y_ply = read_ply(outs["y"] / "surfaces" / "sheet_00003.ply");
  const auto z_ply = read_ply(outs["z"] / "surfaces" / "sheet_00003.ply");
  ASSERT_EQ(y_ply.positions.size(), z_ply.positions.size());
  for (std::size_t i = 0; i < y_ply.positions.size(); ++i) {
    EXPECT_EQ(z_ply.positions[i], turn(y_ply.positions[i]));  // float32 in the file: the same bits
    EXPECT_EQ(z_ply.velocities[i], turn(y_ply.velocities[i]));
  }
  const auto y_vtu = tetfsi::mesh::io::read_vtu(outs["y"] / "sheet" / "sheet_00003.vtu");
  const auto z_vtu = tetfsi::mesh::io::read_vtu(outs["z"] / "sheet" / "sheet_00003.vtu");
  ASSERT_EQ(y_vtu.points.size(), z_vtu.points.size());
  for (std::size_t i = 0; i < y_vtu.points.size(); ++i) EXPECT_EQ(z_vtu.points[i], turn(y_vtu.points[i]));
  for (std::size_t a = 0; a < y_vtu.point_data.size(); ++a) {
    const auto &fy = y_vtu.point_data[a], &fz = z_vtu.point_data[a];
    ASSERT_EQ(fy.components, 3) << fy.name;
    for (std::size_t i = 0; i + 2 < fy.values.size(); i += 3)
      EXPECT_EQ(Eigen::Vector3d(fz.values[i], fz.values[i + 1], fz.values[i + 2]),
                turn(Eigen::Vector3d(fy.values[i], fy.values[i + 1], fy.values[i + 2])))
          << fy.name;
  }
  EXPECT_EQ(read_text(outs["y"] / "probes.csv"), read_text(outs["z"] / "probes.csv"));
}

TEST(CliRun, DivergenceStopsBeforeWritingAndKeepsEarlierOutput) {
  TempDir dir("run");
  const fs::path scene = dir.path() / "runaway.json", out = dir.path() / "out";
  // x = 1e308 m/s * t overflows to +inf at t = 1.8 s (step 18): a stand-in for a diverging model.
  std::ofstream(scene) << R"({
    "simulation": {"end_time": 3, "dt": 0.1, "frame_rate": 10},
    "solids": [{"name": "runaway", "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
                "material": {"density": 1, "youngs_modulus": 1, "poissons_ratio": 0},
                "motion": {"type": "translation", "velocity": [1e308, 0, 0]}}],
    "export": {"surfaces": "none"}
  })";
  fs::create_directories(out);
  std::ofstream(out / "notes.txt") << "from another run\n";
  int status = -1;
  const std::string msg = tetfsi_run(scene, out, &status);
  EXPECT_EQ(status, 1) << msg;
  EXPECT_NE(msg.find("step 18 (t = 1.8 s): non-finite value in solid 'runaway': position of vertex"),
            std::string::npos) << msg;

  // Frames 0..17 are whole and listed; frame 18 was never written; the other file is untouched.
  const auto frames = lines(vtk_describe(out / "runaway.pvd", &status));
  EXPECT_EQ(status, 0);
  EXPECT_EQ(frames.size(), 18u);
  EXPECT_TRUE(fs::exists(out / "runaway" / "runaway_00017.vtu"));
  EXPECT_FALSE(fs::exists(out / "runaway" / "runaway_00018.vtu"));
  EXPECT_EQ(read_text(out / "notes.txt"), "from another run\n");
  for (const auto& e : fs::recursive_directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  EXPECT_EQ(read_csv(out / "stats.csv").rows.size(), 17u);
  EXPECT_NE(read_text(out / "run.log").find("[error] step 18"), std::string::npos);
}

TEST(CliRun, ExportOptionsSelectFramesAndFormats) {
  TempDir dir("run");
  std::string scene_text = kSpinning;
  const std::string probes_key = "\"probes\"";
  scene_text.replace(scene_text.find(probes_key), probes_key.size(),
                     "\"export\": {\"vtu\": true, \"surfaces\": \"obj\", \"every_n_frames\": 2}, \"probes\"");
  const fs::path scene = dir.path() / "spin.json", out = dir.path() / "out";
  std::ofstream(scene) << scene_text;
  int status = -1;
  const std::string log = tetfsi_run(scene, out, &status);
  ASSERT_EQ(status, 0) << log;
  const auto frames = lines(vtk_describe(out / "sheet.pvd", &status));
  ASSERT_EQ(frames.size(), 3u);  // frames 0, 2, 4 of 0..4
  EXPECT_TRUE(fs::exists(out / "surfaces" / "sheet_00002.obj"));
  EXPECT_FALSE(fs::exists(out / "surfaces" / "sheet_00001.obj"));
  EXPECT_FALSE(fs::exists(out / "surfaces" / "sheet_00000.ply"));
  // The OBJ has the 8 vertices and 12 triangles of the slab.
  const auto obj = lines(read_text(out / "surfaces" / "sheet_00004.obj"));
  EXPECT_EQ(std::count_if(obj.begin(), obj.end(), [](const std::string& l) { return l.rfind("v ", 0) == 0; }), 8);
  EXPECT_EQ(std::count_if(obj.begin(), obj.end(), [](const std::string& l) { return l.rfind("f ", 0) == 0; }), 12);
}

TEST(Progress, EtaLeavesOutSetUpAndFollowsTheRecentStepCost) {
  // 30 s of set-up, then 1 s of wall time per 0.01 s simulated up to t = 0.5 of 1 s, then 2 s
  // per step: after the change the estimate follows the new cost (a tenth of the run).
  tetfsi::run::EtaEstimate eta(1.0);
  EXPECT_LT(eta.seconds_left(), 0);
  double wall = 30.0;
  eta.add(0.0, wall);
  EXPECT_LT(eta.seconds_left(), 0);  // one sample: no rate yet
  eta.add(0.01, wall += 20.0);        // the first step's one-off costs are left out
  EXPECT_LT(eta.seconds_left(), 0);
  for (int k = 2; k <= 50; ++k) eta.add(0.01 * k, wall += 1.0);
  EXPECT_NEAR(eta.seconds_left(), 50.0, 1e-9);  // 0.5 s left at 100 s per simulated second
  for (int k = 51; k <= 70; ++k) eta.add(0.01 * k, wall += 2.0);
  // 0.3 s left at (nearly) 200 s per simulated second: within 15% after two tenths of the run.
  EXPECT_NEAR(eta.seconds_left(), 60.0, 0.15 * 60.0);
  EXPECT_GT(eta.seconds_left(), 50.0);
}
