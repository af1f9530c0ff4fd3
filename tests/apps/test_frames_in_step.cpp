// Frames in step (issue 20): frame N of every object is the state at the same time t_N. In a
// coupled run the fluid solver's mesh is the one the step ran on, at the solids' positions of the
// step's start; the fluid frame must be drawn with its nodes moved to the solids at the step's end
// (coupling::CoupledStepper::fluid_node_positions), so that every solid surface vertex has a
// fluid vertex at the same position in the same frame. Before the fix the fluid frame N matched
// solid frame N - 1 and was millimetres off frame N.
//
// Checked through `tetfsi run`, one frame per step:
//  - smoke on the two hanging sheets (data/scenes/smoke_sheets_ci.json, 3 steps of 1/50 s): the
//    fluid .vtu against each sheet's .vtu, to round-off (1e-12 of the domain's diagonal);
//  - the floating block (data/scenes/floating_block_ci.json, 3 steps of 1/120 s), a liquid with
//    a free surface: the same for the fluid .vtu, and every wet solid surface vertex (level set
//    < 0 at its fluid node) is a vertex of the liquid surface PLY (float32: 1e-6 of the diagonal),
//    the marching-tets one (export.liquid_surface "tets"), whose vertices on solids are fluid
//    nodes (the smooth surface's are voxel crossings: fluid/README.md, "Surfaces for renderers");
//  - the fluid runner's rotating paddle (data/scenes/paddle.json, 3 steps of 1/50 s, kinematic
//    solid moving the fluid mesh): every paddle PLY vertex is a fluid .vtu point (float32).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "mesh/io/vtu_reader.hpp"
#include "csv.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi;

namespace {

/// Runs `scene_file` (under data/scenes) with its end time and frame rate set to `steps` steps of
/// dt, one frame per step, into a fresh directory; returns the output directory.
/// `edit` (if given) changes the scene further.
fs::path run_one_frame_per_step(const test::TempDir& dir, const std::string& scene_file, double dt, int steps,
                                const std::function<void(nlohmann::json&)>& edit = {}) {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes" / scene_file);
  nlohmann::json scene = nlohmann::json::parse(in);
  if (edit) edit(scene);
  scene["simulation"]["dt"] = dt;
  scene["simulation"]["frame_rate"] = 1.0 / dt;
  scene["simulation"]["end_time"] = steps * dt;
  scene["export"]["vtu"] = true;
  scene["export"]["surfaces"] = "ply";
  const fs::path json = dir.path() / scene_file;
  std::ofstream(json) << scene.dump(2);
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string msg = test::run_command(
      std::string(TETFSI_BINARY) + " run " + json.string() + " -q --out " + out.string() + " 2>&1", &status);
  EXPECT_EQ(status, 0) << msg;
  return out;
}

mesh::io::UnstructuredGrid frame_grid(const fs::path& out, const std::string& object, int frame) {
  return mesh::io::read_vtu(out / object / fmt::format("{}_{:05d}.vtu", object, frame));
}

/// The points of a tet grid on its boundary (in a face of one tet only).
std::vector<int> boundary_points(const mesh::io::UnstructuredGrid& g) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, int> count;
  for (int c = 0; c < g.num_cells(); ++c) {
    const std::int64_t* t = &g.connectivity[g.offsets[c] - 4];
    for (const auto& f : kFace) {
      std::array<int, 3> key{int(t[f[0]]), int(t[f[1]]), int(t[f[2]])};
      std::sort(key.begin(), key.end());
      ++count[key];
    }
  }
  std::vector<char> on(g.num_points(), 0);
  for (const auto& [face, n] : count)
    if (n == 1)
      for (int v : face) on[v] = 1;
  std::vector<int> out;
  for (int v = 0; v < g.num_points(); ++v)
    if (on[v]) out.push_back(v);
  return out;
}

/// Index of the point of `points` nearest to x and its distance.
std::pair<int, double> nearest(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& x) {
  std::pair<int, double> best{-1, std::numeric_limits<double>::infinity()};
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const double d = (points[i] - x).norm();
    if (d < best.second) best = {i, d};
  }
  return best;
}

const mesh::io::DataArray& field(const mesh::io::UnstructuredGrid& g, const std::string& name) {
  for (const auto& a : g.point_data)
    if (a.name == name) return a;
  throw std::runtime_error("no point field " + name);
}

/// The largest distance from a surface vertex of the solid's grid to the nearest fluid point,
/// over frames 1..steps (frame 0 is the initial mesh, in step by construction).
double max_solid_to_fluid_gap(const fs::path& out, const std::string& solid, int steps) {
  double worst = 0;
  for (int f = 1; f <= steps; ++f) {
    const auto fluid = frame_grid(out, "fluid", f);
    const auto body = frame_grid(out, solid, f);
    for (int v : boundary_points(body)) worst = std::max(worst, nearest(fluid.points, body.points[v]).second);
  }
  return worst;
}

double box_diagonal(const fs::path& scene) {
  std::ifstream in(scene);
  const auto js = nlohmann::json::parse(in);
  Eigen::Vector3d lo, hi;
  for (int k = 0; k < 3; ++k) lo[k] = js["domain"]["lo"][k], hi[k] = js["domain"]["hi"][k];
  return (hi - lo).norm();
}

}  // namespace

TEST(FramesInStep, CoupledSmokeFrameHasTheSheetsVerticesOfTheSameFrame) {
  test::TempDir dir("frames_smoke");
  const int steps = 3;
  const fs::path out = run_one_frame_per_step(dir, "smoke_sheets_ci.json", 0.02, steps);
  const double tol = 1e-12 * box_diagonal(dir.path() / "smoke_sheets_ci.json");
  for (const char* sheet : {"deflector", "catcher"}) {
    // The sheets did move (sagging and pushed by the jet): the check can fail.
    const auto start = frame_grid(out, sheet, 0), end = frame_grid(out, sheet, steps);
    double moved = 0;
    for (int v = 0; v < start.num_points(); ++v) moved = std::max(moved, (end.points[v] - start.points[v]).norm());
    EXPECT_GT(moved, 1e-4) << sheet;
    const double gap = max_solid_to_fluid_gap(out, sheet, steps);
    std::printf("%s: moved %.3g m, largest gap to the fluid %.3g m\n", sheet, moved, gap);
    EXPECT_LE(gap, tol) << sheet << ": a surface vertex is " << gap << " m from the fluid's nearest vertex";
  }
}

// Remeshed every step: the fluid solver's mesh is then not the stepper's mesh, and the frame is
// drawn on the solver's mesh moved to the solids before the remesh.
TEST(FramesInStep, CoupledSmokeFrameIsInStepWhenRemeshedEveryStep) {
  test::TempDir dir("frames_remesh");
  const int steps = 3;
  const fs::path out = run_one_frame_per_step(dir, "smoke_sheets_ci.json", 0.02, steps, [](nlohmann::json& scene) {
    scene["coupling"]["mesh_update"] = "remesh_every_step";
  });
  const test::Csv stats = test::read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), static_cast<std::size_t>(steps));
  // The first step's remesh is kept (a later one that does not beat the moved mesh is rejected).
  EXPECT_EQ(stats.at(0, "remeshed"), 1.0);
  const double tol = 1e-12 * box_diagonal(dir.path() / "smoke_sheets_ci.json");
  for (const char* sheet : {"deflector", "catcher"}) {
    const double gap = max_solid_to_fluid_gap(out, sheet, steps);
    std::printf("%s (remeshed every step): largest gap to the fluid %.3g m\n", sheet, gap);
    EXPECT_LE(gap, tol) << sheet << ": a surface vertex is " << gap << " m from the fluid's nearest vertex";
  }
}

TEST(FramesInStep, CoupledLiquidFrameAndSurfaceHaveTheBlocksVerticesOfTheSameFrame) {
  test::TempDir dir("frames_liquid");
  const int steps = 3;
  const fs::path out = run_one_frame_per_step(dir, "floating_block_ci.json", 1.0 / 120, steps, [](nlohmann::json& s) {
    s["export"]["liquid_surface"] = {{"type", "tets"}};
  });
  const double diagonal = box_diagonal(dir.path() / "floating_block_ci.json");
  const double gap = max_solid_to_fluid_gap(out, "block", steps);
  std::printf("block: largest gap to the fluid %.3g m\n", gap);
  EXPECT_LE(gap, 1e-12 * diagonal) << "a block surface vertex is " << gap << " m from the fluid's nearest vertex";
  // The wet part of the block's surface is in the liquid surface of the same frame.
  double worst = 0;
  int wet = 0;
  for (int f = 1; f <= steps; ++f) {
    const auto fluid = frame_grid(out, "fluid", f);
    const auto body = frame_grid(out, "block", f);
    const auto& phi = field(fluid, "level_set").values;
    const auto liquid = test::read_ply(out / "surfaces" / fmt::format("liquid_{:05d}.ply", f));
    for (int v : boundary_points(body)) {
      const auto [node, d] = nearest(fluid.points, body.points[v]);
      if (!(phi[node] < 0)) continue;
      ++wet;
      worst = std::max(worst, nearest(liquid.positions, body.points[v]).second);
    }
  }
  std::printf("block: %d wet surface vertices, largest gap to the liquid surface %.3g m\n", wet, worst);
  EXPECT_GT(wet, 10);
  EXPECT_LE(worst, 1e-6 * diagonal) << "a wet block vertex is " << worst << " m from the liquid surface's nearest vertex";
}

TEST(FramesInStep, FluidRunnerFrameHasTheMovingPaddlesVertices) {
  test::TempDir dir("frames_paddle");
  const int steps = 3;
  const fs::path out = run_one_frame_per_step(dir, "paddle.json", 0.02, steps);
  const double tol = 1e-6 * box_diagonal(dir.path() / "paddle.json");  // the PLY is float32
  const auto first = test::read_ply(out / "surfaces" / "paddle_00000.ply");
  for (int f = 1; f <= steps; ++f) {
    const auto fluid = frame_grid(out, "fluid", f);
    const auto paddle = test::read_ply(out / "surfaces" / fmt::format("paddle_{:05d}.ply", f));
    // The remesh renumbers the surface: how far the paddle moved is measured to frame 0's
    // nearest vertex.
    double moved = 0, gap = 0;
    for (const Eigen::Vector3d& x : paddle.positions) {
      moved = std::max(moved, nearest(first.positions, x).second);
      gap = std::max(gap, nearest(fluid.points, x).second);
    }
    std::printf("paddle frame %d: moved %.3g m, largest gap to the fluid %.3g m\n", f, moved, gap);
    EXPECT_GT(moved, 1e-3) << "frame " << f;  // the tip moves 2 rad/s x 0.2 m x 0.02 s = 8 mm per step
    EXPECT_LE(gap, tol) << "frame " << f << ": a paddle vertex is " << gap << " m from the fluid's nearest vertex";
  }
}
