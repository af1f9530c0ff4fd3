// The coupled runner through the command line: a light ball released in a closed tank of water
// (data/scenes/light_ball_in_water.json) rises with the buoyant acceleration corrected by the
// added mass of a sphere, a = g (ρ_f − ρ_s) / (ρ_s + ρ_f/2) (added mass ½ρ_f V, Lamb 1932, §92): g/2 here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

/// Runs the committed scene with the near-solid edge length `edge` [m] for `end_time` [s]; returns
/// the acceleration 2 y / t² of the ball's centre at the end, and the output folder's probes.
double ball_acceleration(const TempDir& dir, double edge, double end_time, Csv* stats = nullptr) {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/light_ball_in_water.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["mesh"]["edge_length_near_solids"] = edge;
  scene["mesh"]["facet_distance"] = edge / 10;
  scene["simulation"]["end_time"] = end_time;
  const fs::path file = dir.path() / ("ball_" + std::to_string(edge) + ".json");
  std::ofstream(file) << scene.dump(2);
  const fs::path out = dir.path() / ("out_" + std::to_string(edge));
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " +
                                          out.string() + " --quiet 2>&1",
                                      &status);
  EXPECT_EQ(status, 0) << log;
  if (stats) *stats = read_csv(out / "stats.csv");
  const Csv probes = read_csv(out / "probes.csv");
  const std::size_t last = probes.rows.size() - 1;
  const double t = probes.at(last, "time"), y = probes.at(last, "centre_y");
  return 2 * y / (t * t);
}

}  // namespace

TEST(CoupledRun, LightBallRisesWithAddedMassCorrectedBuoyancy) {
  TempDir dir("coupled");
  const double g = 9.81, exact = g * (1000.0 - 500.0) / (500.0 + 500.0);
  Csv stats;
  const double coarse = ball_acceleration(dir, 0.025, 0.04, &stats);
  const double fine = ball_acceleration(dir, 0.015, 0.01);
  std::printf("light ball: a = %.4f (edge a/4), %.4f (edge 0.15 a); exact %.4f m/s^2\n", coarse, fine, exact);
  // The nodal-pressure fluid under-resolves the added mass on coarse meshes (fluid/README.md
  // measures -10.7% at h/a = 0.24 and second-order convergence). Seen: +11.1% and +6.4%.
  EXPECT_LT(std::abs(fine - exact), std::abs(coarse - exact));
  EXPECT_NEAR(coarse, exact, 0.15 * exact);
  EXPECT_NEAR(fine, exact, 0.08 * exact);
  // Every step converged to the coupled solver's tolerance (1e-8 per block).
  for (std::size_t r = 0; r < stats.rows.size(); ++r) EXPECT_LE(stats.at(r, "solver_residual"), 1e-8);
}

TEST(CoupledRun, SceneWithoutCouplingBlockRunsCoupledWithDefaults) {
  // Fluid + deformable solids and no `coupling` block: the coupled runner takes it with the
  // block's defaults (simultaneous, schur_cg, fluid mesh remeshed when needed).
  TempDir dir("defaults");
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/light_ball_in_water.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene.erase("coupling");
  scene["simulation"]["end_time"] = 0.01;
  const fs::path file = dir.path() / "ball.json";
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string out = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " +
                                          (dir.path() / "o").string() + " --quiet 2>&1",
                                      &status);
  EXPECT_EQ(status, 0) << out;
  std::ifstream log(dir.path() / "o" / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  EXPECT_NE(text.find("runner: coupled"), std::string::npos) << text;
  EXPECT_NE(text.find("scheme simultaneous, solver schur_cg"), std::string::npos) << text;
  EXPECT_NE(text.find("mesh update remesh_when_needed"), std::string::npos) << text;
}

TEST(CoupledRun, BallRisesSeveralCellsWhileTheFluidMeshFollows) {
  // The ball rises about 0.2 m = 8 near-solid cells in 0.3 s: the fluid vertices follow it
  // (coupling/mesh_update.hpp; the stiffened Laplacian keeps the min dihedral angle above 4 deg
  // here, so no remesh is needed). Position against y = ½ (g/2) t²; at this
  // coarse size the early acceleration is +11% too high (test above) and the closed tank's walls
  // slow the ball as it nears the lid, so the band is 10%. Seen: +0.3% (0.2214 m against 0.2207 m).
  TempDir dir("rise");
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/light_ball_in_water.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["simulation"]["end_time"] = 0.3;
  scene["simulation"]["dt"] = 0.01;
  scene["fluid"]["remesh_band"] = 0.1;
  const fs::path file = dir.path() / "rise.json";
  std::ofstream(file) << scene.dump(2);
  const fs::path out = dir.path() / "o";
  int status = -1;
  const std::string log =
      run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() + " --quiet 2>&1",
                  &status);
  ASSERT_EQ(status, 0) << log;
  const Csv stats = read_csv(out / "stats.csv");
  const Csv probes = read_csv(out / "probes.csv");
  int remeshes = 0;
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    remeshes += stats.at(r, "remeshed") > 0;  // reported, not required
    EXPECT_GT(stats.at(r, "min_dihedral"), 1.0) << "step " << r + 1;
    EXPECT_LE(stats.at(r, "solver_residual"), 1e-8);
  }
  const std::size_t last = probes.rows.size() - 1;
  const double t = probes.at(last, "time"), y = probes.at(last, "centre_y");
  const double exact = 0.5 * (9.81 / 2) * t * t;
  std::printf("ball rise: y(%.2f s) = %.4f m against %.4f m, %d remesh(es)\n", t, y, exact, remeshes);
  EXPECT_NEAR(y, exact, 0.10 * exact);
  // The solid keeps its volume (rubber, ν = 0.3, nearly rigid here): within 0.5%.
  EXPECT_NEAR(probes.at(last, "ball_volume"), probes.at(0, "ball_volume"), 5e-3 * probes.at(0, "ball_volume"));
}

TEST(CoupledRun, KinematicPaddleAndDeformableFlapRunCoupled) {
  // data/scenes/paddle_flap.json: a kinematic paddle (rotation at 4 rad/s about the vertical
  // axis through (0, 0.4, 0)) and a deformable flap clamped to the floor in one closed smoke box:
  // the coupled runner takes it (before: refused). The paddle's nodes land where the rotation puts
  // them (its tip node, at rest (0.15, 0.4, 0): d = R(4t) X − X to 1e-9 m); the flap, moved only by
  // the stirred smoke, deforms (seen: its top moves 3.8e-4 m at most).
  TempDir dir("paddle_flap");
  const fs::path out = dir.path() / "o";
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " +
                                          (fs::path(TETFSI_SOURCE_DIR) / "data/scenes/paddle_flap.json").string() +
                                          " --out " + out.string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << log;
  std::ifstream run_log(out / "run.log");
  const std::string text((std::istreambuf_iterator<char>(run_log)), {});
  EXPECT_NE(text.find("runner: coupled"), std::string::npos);
  EXPECT_NE(text.find("1 kinematic solid(s)"), std::string::npos);
  const Csv probes = read_csv(out / "probes.csv");
  double flap = 0;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    const double t = probes.at(r, "time"), a = 4 * t;
    EXPECT_NEAR(probes.at(r, "paddle_tip_x"), 0.15 * std::cos(a) - 0.15, 1e-9) << "t = " << t;
    EXPECT_NEAR(probes.at(r, "paddle_tip_y"), 0.0, 1e-9);
    EXPECT_NEAR(probes.at(r, "paddle_tip_z"), -0.15 * std::sin(a), 1e-9) << "t = " << t;
    flap = std::max(flap, std::hypot(probes.at(r, "flap_top_x"), probes.at(r, "flap_top_z")));
  }
  std::printf("paddle and flap: largest flap top displacement %.3g m\n", flap);
  EXPECT_GT(flap, 1e-5);
  EXPECT_LT(flap, 0.05);
}

TEST(CoupledRun, MeshMotionByAmgGivesTheRunOfTheFactorization) {
  // coupling.mesh_motion_solver: the factorized motion and the AMG-preconditioned CG solve one
  // system to the same tolerance (1e-8), so the probes agree to far below the discretization's
  // error (here to 1e-6 of each column's scale); run.log names the solver.
  const TempDir dir("mesh_motion_solver");
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/light_ball_in_water.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["simulation"]["end_time"] = 0.03;
  auto run = [&](const std::string& solver) {
    scene["coupling"]["mesh_motion_solver"] = solver;
    const fs::path file = dir.path() / (solver + ".json"), out = dir.path() / solver;
    std::ofstream(file) << scene.dump(2);
    int status = -1;
    const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " +
                                            out.string() + " --threads 1 2>&1",
                                        &status);
    EXPECT_EQ(status, 0) << log;
    std::ifstream run_log(out / "run.log");
    const std::string text((std::istreambuf_iterator<char>(run_log)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("(motion: " + solver + ")"), std::string::npos) << text;
    return read_csv(out / "probes.csv");
  };
  const Csv a = run("cholesky"), b = run("amg");
  ASSERT_EQ(a.header, b.header);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_GE(a.rows.size(), 3u);
  for (std::size_t c = 0; c < a.header.size(); ++c) {
    double scale = 0;
    for (const auto& row : a.rows) scale = std::max(scale, std::abs(row[c]));
    for (std::size_t r = 0; r < a.rows.size(); ++r)
      EXPECT_NEAR(b.rows[r][c], a.rows[r][c], 1e-6 * std::max(scale, 1e-12)) << a.header[c] << ", row " << r;
  }
}

TEST(CoupledRun, CompareSolversTimesTheSameSystemAndLeavesTheRunUnchanged) {
  // coupling.compare_solvers solves every step's system of eq. (7) again with BiCGSTAB and UMFPACK
  // and its fluid block with the fluid's projection solver, and discards the answers: the probes
  // are those of the run without it, bit for bit, and every compared solve reached its tolerance
  // (iterations >= 0; UMFPACK is direct: 0).
  const TempDir dir("compare_solvers");
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/light_ball_in_water.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["simulation"]["end_time"] = 0.03;
  scene["coupling"]["compare_solvers"] = nlohmann::json::array();  // the default, given: none
  auto run = [&](const std::string& name) {
    const fs::path file = dir.path() / (name + ".json"), out = dir.path() / name;
    std::ofstream(file) << scene.dump(2);
    int status = -1;
    const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " +
                                            out.string() + " --quiet --threads 1 2>&1",
                                        &status);
    EXPECT_EQ(status, 0) << log;
    return out;
  };
  const fs::path plain = run("plain");
  scene["coupling"]["compare_solvers"] = {"projection", "bicgstab", "umfpack"};
  const fs::path compared = run("compared");
  const Csv a = read_csv(plain / "probes.csv"), b = read_csv(compared / "probes.csv");
  ASSERT_EQ(a.header, b.header);
  ASSERT_GE(a.rows.size(), 3u);
  EXPECT_EQ(a.rows, b.rows);
  const Csv stats = read_csv(compared / "stats.csv");
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_GT(stats.at(r, "compare_projection_iterations"), 0) << "step " << r + 1;
    EXPECT_GT(stats.at(r, "compare_bicgstab_iterations"), 0) << "step " << r + 1;
    EXPECT_EQ(stats.at(r, "compare_umfpack_iterations"), 0) << "step " << r + 1;
    EXPECT_GT(stats.at(r, "compare_umfpack_seconds"), 0) << "step " << r + 1;
  }
}

TEST(CoupledRun, SmokeOnSheetsIsBitwiseTheSameOnOneThreadAndOnTwo) {
  // The flagship's CI scene runs every threaded piece of the coupled step: the lagged solves'
  // block-diagonal preconditioner (smoke on rubber sheets: the solid's solve on a second thread
  // beside the V-cycle), the two sheets' factors solved side by side, the blocked Gram-Schmidt, the
  // point locator's grid built by fixed ranges of tets, the gathers. Every sum is taken in an order
  // that does not depend on the threads, so the probes and every frame file are the same bytes.
  const TempDir dir("coupled_threads");
  const fs::path scene = fs::path(TETFSI_SOURCE_DIR) / "data/scenes/smoke_sheets_ci.json";
  auto run = [&](int threads) {
    const fs::path out = dir.path() / ("threads_" + std::to_string(threads));
    int status = -1;
    const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + scene.string() + " --out " +
                                            out.string() + " --threads " + std::to_string(threads) + " --quiet 2>&1",
                                        &status);
    EXPECT_EQ(status, 0) << log;
    return out;
  };
  const fs::path one = run(1), two = run(2);
  auto bytes = [](const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  int compared = 0;
  for (const auto& entry : fs::recursive_directory_iterator(one)) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), one);
    if (relative == "stats.csv" || relative == "run.log") continue;  // wall times, the thread count
    ASSERT_TRUE(fs::exists(two / relative)) << relative;
    EXPECT_EQ(bytes(entry.path()), bytes(two / relative)) << relative;
    ++compared;
  }
  EXPECT_GT(compared, 10);
  EXPECT_FALSE(bytes(one / "probes.csv").empty());
}
