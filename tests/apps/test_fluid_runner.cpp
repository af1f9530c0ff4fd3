// `tetfsi run` with the fluid runner (apps/run/fluid_runner.cpp), end to end through the binary:
//  - still liquid in a closed box under gravity: velocity stays at solver round-off
//    (< 1e-8 sqrt(g H)) and the pressure difference between two depths is rho g dz within 1%;
//  - smoke_plume.json (shortened): every projection leaves max |div| <= 1e-8 U/h, smoke has risen
//    above the inflow and not off to the side, the fluid frames read back with VTK match stats.csv;
//  - paddle.json (shortened): the fluid is remeshed every step with positive dihedral angles,
//    one stats row per step, the exported paddle surface moves with v = omega x (x - c);
//  - a misspelt fluid key exits 2 naming its JSON pointer; deformable solids go to another runner.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "cli_helpers.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

/// Runs `scene` (written to dir/scene.json) into dir/out; returns the output folder.
fs::path run_scene(const TempDir& dir, const json& scene, int* status, std::string* log) {
  const fs::path file = dir.path() / "scene.json", out = dir.path() / "out";
  std::ofstream(file) << scene.dump(2);
  *log = tetfsi_cmd("run " + file.string() + " --out " + out.string() + " --quiet --threads 1", status);
  return out;
}

/// `tetfsi run` of `scene` in a temporary folder named `name`: exit status, log, output folder.
struct SceneRun {
  SceneRun(const std::string& name, const json& scene) : dir(name) { out = run_scene(dir, scene, &status, &log); }
  TempDir dir;
  int status = -1;
  std::string log;
  fs::path out;
};

}  // namespace

TEST(FluidRunner, StillLiquidStaysStillWithHydrostaticPressure) {
  const double rho = 1000, g = 9.81, H = 0.4;
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.2, "dt": 0.01, "frame_rate": 10, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [0, 0, 0], "hi": [0.4, 0.4, 0.4]},
    "mesh": {"edge_length": 0.1},
    "fluid": {"type": "liquid", "density": 1000, "solver": {"type": "amg", "tolerance": 1e-12}},
    "probes": [
      {"name": "p_low", "kind": "fluid_point", "point": [0.2, 0.1, 0.2], "quantity": "pressure"},
      {"name": "p_high", "kind": "fluid_point", "point": [0.2, 0.3, 0.2], "quantity": "pressure"},
      {"name": "speed_a", "kind": "fluid_point", "point": [0.1, 0.2, 0.3], "quantity": "speed"},
      {"name": "speed_b", "kind": "fluid_point", "point": [0.3, 0.05, 0.1], "quantity": "speed"},
      {"name": "ke", "kind": "fluid_kinetic_energy"}]
  })");
  const SceneRun run("fluid_still", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const fs::path& out = run.out;
  const Csv stats = read_csv(out / "stats.csv"), probes = read_csv(out / "probes.csv");
  ASSERT_EQ(stats.rows.size(), 20u);
  ASSERT_EQ(probes.rows.size(), 21u);  // t = 0 and every step
  const double u_max = 1e-8 * std::sqrt(g * H);
  // KE = 1/2 rho sum V |u|^2 >= 1/2 rho V_t |u_t|^2: a bound on every tet's speed needs
  // KE <= 1/2 rho V_min u_max^2; 1e-6 m^3 is far below the smallest tet of this 0.1 m mesh.
  const double ke_bound = 0.5 * rho * 1e-6 * u_max * u_max;
  for (std::size_t r = 1; r < probes.rows.size(); ++r) {
    EXPECT_LT(probes.at(r, "speed_a"), u_max) << "row " << r;
    EXPECT_LT(probes.at(r, "speed_b"), u_max) << "row " << r;
    EXPECT_LT(probes.at(r, "ke"), ke_bound) << "row " << r;
    const double dp = probes.at(r, "p_low") - probes.at(r, "p_high");
    EXPECT_NEAR(dp, rho * g * 0.2, 0.01 * rho * g * 0.2) << "row " << r;
  }
  EXPECT_NE(read_text(out / "run.log").find("fluid runner"), std::string::npos);
}

// Hydrostatic pressure in a sphere and in a cylinder (/domain/container, issue 16): closed slip
// walls, liquid at rest under gravity; the cylinder holds a static solid box (a zero translation).
// P1 reproduces the linear p exactly on any container mesh, so the probe difference between two
// depths is rho g dz to 1e-9 relative (solver tolerance 1e-13) and the speed stays below 1e-8 sqrt(gD).
TEST(FluidRunner, HydrostaticPressureInSphericalAndCylindricalContainers) {
  const double rho = 1000, g = 9.81;
  const json sphere = json::parse(R"({"type": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.28, "subdivisions": 2})");
  const json cylinder = json::parse(R"({"type": "cylinder", "center": [0.3, 0.3, 0.3], "radius": 0.25, "length": 0.56,
                                        "axis": "z", "segments": 24})");
  for (const json& container : {sphere, cylinder}) {
    json scene = json::parse(R"({
      "simulation": {"end_time": 0.05, "dt": 0.01, "frame_rate": 20, "gravity": [0, 0, -9.81]},
      "domain": {"lo": [0, 0, 0], "hi": [0.6, 0.6, 0.6]},
      "mesh": {"edge_length": 0.1},
      "fluid": {"type": "liquid", "density": 1000, "solver": {"type": "amg", "tolerance": 1e-13}},
      "probes": [
        {"name": "p_low", "kind": "fluid_point", "point": [0.25, 0.3, 0.12], "quantity": "pressure"},
        {"name": "p_high", "kind": "fluid_point", "point": [0.3, 0.35, 0.42], "quantity": "pressure"},
        {"name": "speed", "kind": "fluid_point", "point": [0.35, 0.25, 0.3], "quantity": "speed"}]
    })");
    scene["domain"]["container"] = container;
    if (container["type"] == "cylinder")
      scene["solids"] = json::parse(R"([{"name": "block", "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
          "placement": {"translation": [0.4, 0.3, 0.3]}, "motion": {"type": "translation", "velocity": [0, 0, 0]},
          "material": {"density": 1000, "youngs_modulus": 1e6, "poissons_ratio": 0.3}}])");
    const SceneRun run("fluid_container_" + container["type"].get<std::string>(), scene);
    ASSERT_EQ(run.status, 0) << run.log;
    // The fluid fills the container, not the box: the logged fluid volume is the container's less
    // the polyhedral deficit and the block (measured: sphere, icosphere level 2 resampled by CGAL,
    // 0.925 of 4/3 pi r^3); between 0.9 and 1 of the exact shape's volume.
    const double r = container["radius"].get<double>(), pi = std::acos(-1.0);
    const double exact = container["type"] == "sphere" ? 4.0 / 3.0 * pi * r * r * r : pi * r * r * 0.56 - 1e-3;
    const std::string log = read_text(run.out / "run.log");
    const auto at = log.find("fluid volume ");
    ASSERT_NE(at, std::string::npos) << log;
    const double volume = std::stod(log.substr(at + 13));
    EXPECT_GT(volume, 0.9 * exact) << container["type"];
    EXPECT_LT(volume, exact) << container["type"];
    const Csv probes = read_csv(run.out / "probes.csv");
    ASSERT_EQ(probes.rows.size(), 6u);
    const double dp_exact = rho * g * 0.3, u_max = 1e-8 * std::sqrt(g * 0.56);
    for (std::size_t r = 1; r < probes.rows.size(); ++r) {
      EXPECT_NEAR(probes.at(r, "p_low") - probes.at(r, "p_high"), dp_exact, 1e-9 * dp_exact)
          << container["type"] << " row " << r;
      EXPECT_LT(probes.at(r, "speed"), u_max) << container["type"] << " row " << r;
    }
    std::printf("%s container: p_low - p_high = %.12g Pa (rho g dz = %.12g Pa)\n",
                container["type"].get<std::string>().c_str(), probes.at(probes.rows.size() - 1, "p_low") -
                probes.at(probes.rows.size() - 1, "p_high"), dp_exact);
  }
}

// A container from a closed surface file (/domain/container type "mesh"): the Stanford bunny
// (3,301 vertices, 1.55 m across, y up) filled with still water under gravity. As for the
// primitives above, P1 reproduces the linear pressure exactly on any container mesh: the probe
// difference between two points 0.4 m apart in height, both more than 0.06 m inside the surface, is
// rho g dz to 1e-9 relative, and the speed stays below 1e-8 sqrt(gD).
TEST(FluidRunner, HydrostaticPressureInAContainerReadFromASurfaceFile) {
  const fs::path bunny = fs::path(TETFSI_SHARED_DIR) / "data" / "bunny.obj";
  ASSERT_TRUE(fs::exists(bunny)) << bunny;
  const double rho = 1000, g = 9.81;
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.02, "dt": 0.01, "frame_rate": 100, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [-0.8, -0.65, -0.8], "hi": [0.8, 0.65, 0.8]},
    "mesh": {"edge_length": 0.1},
    "fluid": {"type": "liquid", "density": 1000, "solver": {"type": "amg", "tolerance": 1e-13}},
    "probes": [
      {"name": "p_low", "kind": "fluid_point", "point": [0, -0.3, 0], "quantity": "pressure"},
      {"name": "p_high", "kind": "fluid_point", "point": [-0.1, 0.1, 0], "quantity": "pressure"},
      {"name": "speed", "kind": "fluid_point", "point": [0.2, -0.3, 0], "quantity": "speed"}]
  })");
  scene["domain"]["container"] = {{"type", "mesh"}, {"file", bunny.string()}};
  const SceneRun run("fluid_container_bunny", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  // The fluid fills the bunny, not the box: the file encloses 0.7493 m^3 (its signed volume); CGAL's
  // mesh of it within 3% of that.
  const std::string log = read_text(run.out / "run.log");
  const auto at = log.find("fluid volume ");
  ASSERT_NE(at, std::string::npos) << log;
  const double volume = std::stod(log.substr(at + 13));
  EXPECT_NEAR(volume, 0.7493, 0.03 * 0.7493);
  const Csv probes = read_csv(run.out / "probes.csv");
  ASSERT_EQ(probes.rows.size(), 3u);
  const double dp_exact = rho * g * 0.4, u_max = 1e-8 * std::sqrt(g * 1.2);
  for (std::size_t r = 1; r < probes.rows.size(); ++r) {
    EXPECT_NEAR(probes.at(r, "p_low") - probes.at(r, "p_high"), dp_exact, 1e-9 * dp_exact) << "row " << r;
    EXPECT_LT(probes.at(r, "speed"), u_max) << "row " << r;
  }
  std::printf("bunny container: fluid volume %.4g m^3, p_low - p_high = %.12g Pa (rho g dz = %.12g Pa)\n", volume,
              probes.at(2, "p_low") - probes.at(2, "p_high"), dp_exact);
}

// A pipe (a cylinder container along x, R = 0.15 m, 0.8 m long) fed through a parabolic inflow
// patch on its x- cap (/domain/inflows/0/profile "parabolic", peak U = 1 m/s) and open on its x+
// cap (/domain/open_patches). Inviscid parallel flow u = U (1 - r^2/R^2) x is an exact steady Euler
// solution with uniform pressure; the inflow's traces carry the profile in (ExitRule::kInflow), and
// after 1.5 s (1.9 flow-through times at the mean speed) mid-pipe has u = U on the axis and 0.75 U
// at r = R/2. Tolerance 0.1 U at edge 0.03 m (5 edges per radius, one velocity per tet), from the
// convergence measured at t = 1.5 s, axis / half-radius error: edge 0.04 m -26% / -25%, 0.03 m
// -6.6% / -6.4%, 0.02 m -3.7% / -2.0%. A uniform inflow would give the same speed at both points.
TEST(FluidRunner, ParabolicInflowThroughAPipeReachesItsOpenEnd) {
  json scene = json::parse(R"({
    "simulation": {"end_time": 1.5, "dt": 0.02, "frame_rate": 10, "gravity": [0, 0, 0]},
    "domain": {"lo": [-0.42, -0.2, -0.2], "hi": [0.42, 0.2, 0.2],
               "container": {"type": "cylinder", "center": [0, 0, 0], "radius": 0.15, "length": 0.8, "axis": "x",
                             "segments": 24},
               "inflows": [{"lo": [-0.41, -0.15, -0.15], "hi": [-0.39, 0.15, 0.15], "velocity": [1, 0, 0],
                            "profile": "parabolic"}],
               "open_patches": [{"lo": [0.39, -0.2, -0.2], "hi": [0.41, 0.2, 0.2]}]},
    "mesh": {"edge_length": 0.03},
    "fluid": {"type": "liquid", "density": 1000, "viscosity": 0},
    "probes": [
      {"name": "u_axis", "kind": "fluid_point", "point": [0, 0, 0], "quantity": "velocity_x"},
      {"name": "u_half", "kind": "fluid_point", "point": [0, 0.075, 0], "quantity": "velocity_x"}]
  })");
  const SceneRun run("fluid_pipe_parabolic", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const Csv probes = read_csv(run.out / "probes.csv");
  const std::size_t last = probes.rows.size() - 1;
  const double axis = probes.at(last, "u_axis"), half = probes.at(last, "u_half");
  std::printf("parabolic pipe inflow, mid-pipe at t = 1.5 s: u(0) = %.4f m/s (exact 1), u(R/2) = %.4f m/s (exact "
              "0.75)\n", axis, half);
  EXPECT_NEAR(axis, 1.0, 0.1);
  EXPECT_NEAR(half, 0.75, 0.1);
  EXPECT_LT(half / axis, 0.9);
}

TEST(FluidRunner, StepsThatDoNotDivideTheFrameEndOnItInTwoEqualSteps) {
  // dt = 0.045 s against frames every 0.05 s: a full step would leave a 0.005 s sliver, so each
  // frame is taken as two steps of 0.025 s, landing exactly on 0.05, 0.10, ... (apps/run/driver.cpp).
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.2, "dt": 0.045, "frame_rate": 20, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [0, 0, 0], "hi": [0.4, 0.4, 0.4]},
    "mesh": {"edge_length": 0.2},
    "fluid": {"type": "liquid", "density": 1000}
  })");
  const SceneRun run("fluid_frame_steps", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const fs::path& out = run.out;
  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 8u);
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_NEAR(stats.at(r, "dt"), 0.025, 1e-12) << "step " << r + 1;
    if (r % 2 == 1) {
      EXPECT_EQ(stats.at(r, "time"), 0.05 * double(r / 2 + 1)) << "step " << r + 1;
    }
  }
}

TEST(FluidRunner, SmokePlumeIsDivergenceFreeAndRises) {
  json scene = committed("smoke_plume.json");
  scene["simulation"]["end_time"] = 0.5;
  scene["probes"] = json::parse(R"([
    {"name": "smoke_axis", "kind": "fluid_point", "point": [0, 0.25, 0], "quantity": "smoke"},
    {"name": "smoke_side", "kind": "fluid_point", "point": [0.3, 0.25, 0.3], "quantity": "smoke"},
    {"name": "vy_axis", "kind": "fluid_point", "point": [0, 0.25, 0], "quantity": "velocity_y"}])");
  const SceneRun run("fluid_plume", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const fs::path& out = run.out;
  const Csv stats = read_csv(out / "stats.csv"), probes = read_csv(out / "probes.csv");
  ASSERT_EQ(stats.rows.size(), 25u);
  // Velocity scale: the 0.5 m/s inflow; mesh size: the edge length at the sphere.
  const double U = 0.5, h = scene["mesh"]["edge_length_near_solids"].get<double>();
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_LE(stats.at(r, "max_divergence"), 1e-8 * U / h) << "step " << r + 1;
    EXPECT_LT(stats.at(r, "residual"), 1e-9) << "step " << r + 1;
    EXPECT_GT(stats.at(r, "min_dihedral"), 0.0);
  }
  // The inflow top is at y = 0; after 0.5 s smoke has reached y = 0.25 above it, rising, while
  // the same height 0.42 m off the axis has (almost) none.
  const std::size_t last = probes.rows.size() - 1;
  EXPECT_GT(probes.at(last, "smoke_axis"), 5e-3);
  EXPECT_GT(probes.at(last, "smoke_axis"), probes.at(last - 5, "smoke_axis"));
  EXPECT_LT(probes.at(last, "smoke_side"), 1e-3 * probes.at(last, "smoke_axis"));
  EXPECT_GT(probes.at(last, "vy_axis"), 0.0);

  // VTK reads back every fluid frame with the counts of stats.csv and the four fields.
  int status = -1;
  const auto frames = lines(vtk_describe(out / "fluid.pvd", &status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(frames.size(), 6u);  // t = 0, 0.1, ..., 0.5
  const std::string expected = " " + std::to_string(int(stats.at(0, "nodes"))) + " " +
                               std::to_string(int(stats.at(0, "tets"))) +
                               " p:pressure:1 p:velocity:3 p:smoke:1 p:temperature:1 c:velocity:3 c:smoke:1 "
                               "c:temperature:1";
  expect_pvd_frames(frames, 0.1, expected);
  EXPECT_TRUE(fs::exists(out / "surfaces" / "sphere_00005.ply"));
}

TEST(FluidRunner, PaddleRemeshesEveryStep) {
  json scene = committed("paddle.json");
  scene["simulation"]["end_time"] = 0.1;
  scene["simulation"]["frame_rate"] = 10;
  const SceneRun run("fluid_paddle", scene);
  ASSERT_EQ(run.status, 0) << run.log;
  const fs::path& out = run.out;
  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 5u);
  const double omega = 2.0, U = omega * 0.2, h = scene["mesh"]["edge_length_near_solids"].get<double>();
  double remeshed = 0.0;
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_GT(stats.at(r, "min_dihedral"), 0.0) << "step " << r + 1;
    EXPECT_GT(stats.at(r, "t_remesh"), 0.0) << "step " << r + 1;
    EXPECT_LE(stats.at(r, "max_divergence"), 1e-8 * U / h) << "step " << r + 1;
    EXPECT_GT(stats.at(r, "kinetic_energy"), 0.0) << "step " << r + 1;  // the paddle stirs the smoke
    remeshed += stats.at(r, "remeshed");
  }
  // Every step moves the mesh with the paddle; CGAL remeshes it when the moved mesh has degraded.
  EXPECT_GE(remeshed, 1.0);
  // The exported paddle surface at t = 0.1 s: vertices turned by omega t about the y axis
  // through c (|x - c| in the xz plane unchanged is checked through v), v = omega y x (x - c).
  const Eigen::Vector3d c(0, 0.4, 0), w(0, omega, 0);
  const auto ply = read_ply(out / "surfaces" / "paddle_00001.ply");
  ASSERT_FALSE(ply.positions.empty());
  ASSERT_EQ(ply.velocities.size(), ply.positions.size());
  for (std::size_t i = 0; i < ply.positions.size(); ++i)
    EXPECT_LT((ply.velocities[i] - w.cross(ply.positions[i] - c)).norm(), 1e-5) << "vertex " << i;
}

TEST(FluidRunner, BadFluidKeyExitsTwoWithPointer) {
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.1, "dt": 0.01},
    "domain": {"lo": [0, 0, 0], "hi": [1, 1, 1], "open_faces": ["y+"]},
    "fluid": {"type": "smoke", "buoyancy_alfa": 0.1}
  })");
  TempDir dir("fluid_bad");
  int status = -1;
  std::string log;
  run_scene(dir, scene, &status, &log);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("/fluid/buoyancy_alfa"), std::string::npos) << log;

  scene["fluid"].erase("buoyancy_alfa");
  scene["domain"]["open_faces"] = {"top"};
  run_scene(dir, scene, &status, &log);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("/domain/open_faces/0"), std::string::npos) << log;
}

TEST(FluidRunner, CommittedScenesValidate) {
  for (const char* name : {"smoke_plume.json", "paddle.json"}) {
    int status = -1;
    const std::string path = std::string(TETFSI_SOURCE_DIR) + "/data/scenes/" + name;
    const std::string log = tetfsi_cmd("validate " + path, &status);
    EXPECT_EQ(status, 0) << name << ": " << log;
  }
}

// Deformable solids (motion none) in a fluid belong to the coupled runner: the fluid runner
// declines the scene; a zero translation is a fixed obstacle and it takes the scene.
TEST(FluidRunner, DeclinesDeformableSolids) {
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.02, "dt": 0.01},
    "domain": {"lo": [-0.5, -0.5, -0.5], "hi": [0.5, 0.5, 0.5]},
    "mesh": {"edge_length": 0.2},
    "fluid": {"type": "smoke"},
    "solids": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.2, "subdivisions": 1},
                "material": {"density": 1000, "youngs_modulus": 1e5, "poissons_ratio": 0.3}}]
  })");
  TempDir dir("fluid_choice");
  int status = -1;
  std::string log;
  fs::path out = run_scene(dir, scene, &status, &log);
  ASSERT_EQ(status, 0) << log;
  const std::string first = read_text(out / "run.log");
  EXPECT_NE(first.find("runner: "), std::string::npos) << first;
  EXPECT_EQ(first.find("runner: fluid"), std::string::npos) << first;
  scene["solids"][0]["motion"] = json::parse(R"({"type": "translation", "velocity": [0, 0, 0]})");
  out = run_scene(dir, scene, &status, &log);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NE(read_text(out / "run.log").find("runner: fluid"), std::string::npos);
}
