// `tetfsi run` of a liquid with a free surface (fluid.fill "regions"; fluid/liquid/), end to end:
//  - dam_break_ci.json (a soft post, coupled through eq. 7): the liquid keeps its volume to 1e-9
//    every step (the level set's volume is restored; the tracking drift before the restoration
//    stays below 1% per step), every frame's liquid surface (the smooth one) is closed, outward and
//    encloses the liquid volume to 0.5%, no surface vertex lies inside the post, and the front has not run ahead of
//    Ritter's dry-bed bound x0 + 2 sqrt(g H) t (Ritter 1892; the inviscid upper limit);
//  - a nozzle (an emitter over a shallow pool) adds liquid while it is on and the volume then
//    stays: the volume grows by at least the nozzle's own box and is constant after it switches off;
//  - an inflow patch on a wall above a pool pours at its flow rate U A;
//  - floating_block_ci.json: a block of half the water's density heaves about the Archimedes
//    draft (coupled through eq. 7) without gaining energy at h = 1/120 s, and stays stable at 1/30 s;
//  - paint_pour_ci.json: a nozzle pours onto a soft ball (coupled): the volume never falls, the
//    liquid surfaces are closed and enclose the liquid volume, the ball sags;
//  - dam_break_ci with the post fixed and surface_edge_length: the mesh is finer at the surface and
//    remeshed as it moves, keeping the volume, every projection divergence-free to 1e-8 U/h;
//  - the time-splitting baseline diverges on the light floating block and runs on a heavy one;
//  - dam_break_ci's column given as a box surface file (a `mesh` region) runs like the box region;
//  - 18 bad values of the free-surface keys give exit 2 naming the key in validate and run alike;
//  - a sphere region with a cap height holds the volume of the spherical cap;
//  - a free surface with a hex8 solid is refused by validate and run alike (exit 2, naming the key).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "ply_reader.hpp"
#include "cli_helpers.hpp"
#include "vtu_tets.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

/// Writes `scene` to dir/scene.json and runs it into dir/out on one thread; returns the console
/// output, `status` the exit code.
std::string run_in(const TempDir& dir, const json& scene, int* status) {
  const fs::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump(2);
  return tetfsi_cmd("run " + file.string() + " --out " + (dir.path() / "out").string() + " --quiet --threads 1", status);
}

/// Volume enclosed by a closed, outward-oriented triangle surface (divergence theorem) [m^3].
double enclosed_volume(const PlyData& ply) {
  double v = 0;
  for (const auto& t : ply.triangles)
    v += ply.positions[t[0]].dot(ply.positions[t[1]].cross(ply.positions[t[2]])) / 6.0;
  return v;
}

/// Liquid volume [m^3] of a frame's fluid grid as written: the P1 level set "level_set" on the
/// grid's tets at the grid's points (fluid::liquid_volume, exact for P1). In a coupled run the
/// points are the fluid nodes moved with the solids to the frame's time, so this is the liquid the
/// frame's surface PLY is drawn from.
double grid_liquid_volume(const fs::path& vtu) {
  const auto g = tetfsi::mesh::io::read_vtu(vtu);
  const auto fm = tetfsi::fluid::build_fluid_mesh(tet_mesh(g));
  const std::vector<double>* phi_points = nullptr;
  for (const auto& a : g.point_data)
    if (a.name == "level_set") phi_points = &a.values;
  if (!phi_points) throw std::runtime_error(vtu.string() + ": no level_set");
  Eigen::VectorXd phi(fm.num_nodes());
  for (int i = 0; i < fm.num_nodes(); ++i) phi[i] = (*phi_points)[fm.node_to_mesh_vertex[i]];
  return tetfsi::fluid::liquid_volume(fm, phi);
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

/// Mean edge length [m] of the triangles of a liquid surface that do not lie on the box [lo, hi]'s
/// walls (the free surface and the solids' wet parts).
double mean_free_edge(const PlyData& ply, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  auto on_wall = [&](const Eigen::Vector3d& x) {
    return ((x - lo).cwiseAbs().array() < 1e-5).any() || ((x - hi).cwiseAbs().array() < 1e-5).any();
  };
  double sum = 0;
  int n = 0;
  for (const auto& t : ply.triangles) {
    if (on_wall(ply.positions[t[0]]) && on_wall(ply.positions[t[1]]) && on_wall(ply.positions[t[2]])) continue;
    for (int k = 0; k < 3; ++k) {
      sum += (ply.positions[t[k]] - ply.positions[t[(k + 1) % 3]]).norm();
      ++n;
    }
  }
  return n > 0 ? sum / n : 0.0;
}

/// Writes the box [lo, hi] as a closed, outward-oriented OBJ surface (12 triangles).
void write_box_obj(const fs::path& file, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::ofstream out(file);
  for (int i = 0; i < 8; ++i)
    out << "v " << (i & 1 ? hi : lo).x() << ' ' << (i & 2 ? hi : lo).y() << ' ' << (i & 4 ? hi : lo).z() << '\n';
  // Corner i+1 (OBJ counts from 1) has x from bit 0, y from bit 1, z from bit 2.
  out << "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\n"
         "f 2 8 6\n";
}

}  // namespace

TEST(LiquidRun, SurfaceFileRegionGivesTheSameLiquidAsTheBox) {
  // dam_break_ci's column as a box region and as the same box read from an OBJ file (a `mesh`
  // region, placed by a scale and a translation): both signed distances are exact for a box, so the
  // level sets, and the runs, agree to round-off.
  TempDir dir("liquid_mesh_region");
  write_box_obj(dir.path() / "column.obj", Eigen::Vector3d(-10, -10, -10), Eigen::Vector3d(4, 6, 10));
  json scene = committed("dam_break_ci.json");
  scene["fluid"]["regions"] = json::parse(R"([{"type": "mesh", "file": "column.obj", "unit_scale": 0.1,
                                               "translation": [0, 0, 0]}])");
  std::ofstream(dir.path() / "mesh_region.json") << scene.dump(2);
  std::ofstream(dir.path() / "box_region.json") << committed("dam_break_ci.json").dump(2);
  Csv stats[2], probes[2];
  for (int k = 0; k < 2; ++k) {
    const std::string name = k == 0 ? "box_region" : "mesh_region";
    int status = -1;
    const std::string log = tetfsi_cmd("run " + (dir.path() / (name + ".json")).string() + " --out " +
                                           (dir.path() / name).string() + " --quiet --threads 1 --end-time 0.1",
                                       &status);
    ASSERT_EQ(status, 0) << log;
    stats[k] = read_csv(dir.path() / name / "stats.csv");
    probes[k] = read_csv(dir.path() / name / "probes.csv");
  }
  ASSERT_EQ(stats[0].rows.size(), stats[1].rows.size());
  ASSERT_GE(stats[0].rows.size(), 2u);
  for (std::size_t r = 0; r < stats[0].rows.size(); ++r) {
    const double v = stats[0].at(r, "liquid_volume");
    EXPECT_NEAR(stats[1].at(r, "liquid_volume"), v, 1e-9 * v) << "step " << r + 1;
  }
  ASSERT_EQ(probes[0].rows.size(), probes[1].rows.size());
  const std::size_t last = probes[0].rows.size() - 1;
  const double ke = probes[0].at(last, "kinetic_energy");
  EXPECT_GT(ke, 0.0);  // the column is falling
  EXPECT_NEAR(probes[1].at(last, "kinetic_energy"), ke, 1e-6 * ke);
  EXPECT_NEAR(probes[1].at(last, "post_top_y"), probes[0].at(last, "post_top_y"), 1e-9);
}

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
  const double g = 9.81, H = 0.6, x0 = 0.4;
  const double h = scene["mesh"]["edge_length_near_solids"].get<double>();
  const double v0 = probes.at(0, "liquid_volume");
  EXPECT_NEAR(v0, 0.4 * 0.6 * 0.4, 0.01 * 0.4 * 0.6 * 0.4);  // the column, as the P1 level set sees it
  // Mechanical energy (fluid kinetic + gravity potential, and the post's): the collapse only
  // dissipates. The kinetic energy leads the potential by one step (gravity and the projection act
  // before the surface moves), so the total overshoots while the column accelerates: measured
  // +0.98% above the first step's total (step 4), then it falls, -4.2% at the end. Bound: 1.5%
  // above the first step, below it at the end.
  const double e1 = stats.at(0, "total_energy");
  for (std::size_t r = 0; r < stats.rows.size(); ++r)
    EXPECT_LE(stats.at(r, "total_energy"), e1 + 0.015 * std::abs(e1)) << "step " << r + 1;
  EXPECT_LT(stats.at(stats.rows.size() - 1, "total_energy"), e1);
  EXPECT_GT(stats.at(stats.rows.size() - 1, "fluid_kinetic"), 0.1 * std::abs(e1));  // the energy did move
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_NEAR(stats.at(r, "liquid_volume"), v0, 1e-9 * v0) << "step " << r + 1;
    EXPECT_LT(std::abs(stats.at(r, "volume_drift")), 0.01) << "step " << r + 1;
    EXPECT_LT(stats.at(r, "solver_residual"), 1e-6) << "step " << r + 1;
    EXPECT_TRUE(std::isfinite(stats.at(r, "total_energy")));
  }
  // Frames: t = 0, 0.05, ..., 0.3 s. The post deforms by millimetres: no liquid vertex may lie
  // deeper than 1 cm inside its rest box.
  const Eigen::Vector3d post_lo(1.04 + 0.01, 0.05 + 0.01, 0.14 + 0.01), post_hi(1.16 - 0.01, 0.35 - 0.01, 0.26 - 0.01);
  double front = 0, worst_volume = 0;
  for (int frame = 0; frame <= 6; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "liquid_%05d.ply", frame);
    const auto ply = read_ply(out / "surfaces" / name);
    ASSERT_FALSE(ply.triangles.empty());
    ASSERT_EQ(ply.velocities.size(), ply.positions.size());
    EXPECT_EQ(open_edges(ply), 0) << "frame " << frame;
    // The smooth surface (export.liquid_surface default) encloses the liquid's volume by its iso
    // shift, aimed at 1e-4: measured at most 7e-5. Bound: 0.5% (issue 41).
    EXPECT_NEAR(enclosed_volume(ply), v0, 5e-3 * v0) << "frame " << frame;
    worst_volume = std::max(worst_volume, std::abs(enclosed_volume(ply) / v0 - 1));
    const double t = 0.05 * frame;
    front = 0;
    for (const auto& x : ply.positions) {
      front = std::max(front, x.x());
      const bool inside_post = ((x - post_lo).array() > 0).all() && ((post_hi - x).array() > 0).all();
      EXPECT_FALSE(inside_post) << "frame " << frame << ": liquid vertex inside the post";
    }
    EXPECT_LE(front, x0 + 2 * std::sqrt(g * H) * t + h) << "frame " << frame;
  }
  EXPECT_GT(front, x0 + 2 * h);  // the column has collapsed and run out
  std::printf("dam break: the liquid surfaces enclose the liquid volume to %.2e on every frame\n", worst_volume);
}

TEST(LiquidRun, FreeSurfaceWithHexSolidIsRefused) {
  json scene = committed("floating_block_ci.json");
  scene["solids"][0]["model"] = {{"type", "hex8"}};
  TempDir dir("liquid_refused");
  const fs::path file = dir.path() / "scene.json";
  std::ofstream(file) << scene.dump(2);
  int validate_status = -1, run_status = -1;
  const std::string validate = tetfsi_cmd("validate " + file.string(), &validate_status);
  const std::string run = tetfsi_cmd("run " + file.string() + " --out " + (dir.path() / "out").string(), &run_status);
  EXPECT_EQ(validate_status, 2) << validate;
  EXPECT_EQ(run_status, 2) << run;
  EXPECT_NE(validate.find("/solids/0/model/type"), std::string::npos) << validate;
  EXPECT_NE(run.find("/solids/0/model/type"), std::string::npos) << run;
}

namespace {

/// Heave of floating_block_ci.json at time step h for `duration` [s]: the centre's displacement
/// at every step and the liquid volume at t = 0 (runs the binary).
struct Heave {
  std::vector<double> y;
  double liquid_volume = 0;
  std::vector<double> extrema() const {
    std::vector<double> e;
    for (std::size_t i = 1; i + 1 < y.size(); ++i)
      if ((y[i] - y[i - 1]) * (y[i + 1] - y[i]) < 0) e.push_back(y[i]);
    return e;
  }
};

Heave floating_block(double h, double duration, const std::string& name) {
  json scene = committed("floating_block_ci.json");
  scene["simulation"]["dt"] = h;
  scene["simulation"]["frame_rate"] = 1.0 / h;
  scene["simulation"]["end_time"] = duration;
  TempDir dir(name);
  const fs::path file = dir.path() / "scene.json", out = dir.path() / "out";
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string log = tetfsi_cmd("run " + file.string() + " --out " + out.string() + " --quiet --threads 1", &status);
  EXPECT_EQ(status, 0) << log;
  Heave heave;
  if (status != 0) return heave;
  const Csv probes = read_csv(out / "probes.csv"), stats = read_csv(out / "stats.csv");
  heave.liquid_volume = probes.at(0, "liquid_volume");
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    heave.y.push_back(probes.at(r, "centre_y"));
    EXPECT_NEAR(probes.at(r, "liquid_volume"), heave.liquid_volume, 1e-9 * heave.liquid_volume) << "row " << r;
  }
  for (std::size_t r = 0; r < stats.rows.size(); ++r) EXPECT_TRUE(std::isfinite(stats.at(r, "total_energy")));
  return heave;
}

/// Archimedes: draft d = (rho_s / rho_f) b for the block height b = 0.1 m; the water level rises by
/// the displaced volume, L = (V_liquid + A_block d) / A_tank, so the centre (released at 0.27 m)
/// floats at L - d + b/2: its displacement from the release.
double archimedes_displacement(double liquid_volume) {
  const double b = 0.1, d = 0.5 * b, a_block = 0.2 * 0.2, a_tank = 0.6 * 0.6, y0 = 0.27;
  return (liquid_volume + a_block * d) / a_tank - d + 0.5 * b - y0;
}

double mean_of_midpoints(const std::vector<double>& e) {
  double mean = 0;
  for (std::size_t k = 1; k < e.size(); ++k) mean += 0.5 * (e[k - 1] + e[k]);
  return mean / static_cast<double>(e.size() - 1);
}

}  // namespace

TEST(LiquidRun, FloatingBlockHeavesAboutTheArchimedesDraft) {
  // h = 1/120 s (omega h = 0.08 for the heave), 1.5 s, two and a half periods. The mean of
  // consecutive extrema of the heave must be the Archimedes position within 2% of the draft;
  // released at rest z0 from it, an energy-conserving heave never swings further than z0 (the
  // surface's potential energy is least when flat): every swing within z0, each no larger than the
  // one before.
  const Heave heave = floating_block(1.0 / 120, 1.5, "liquid_floating_block");
  const std::vector<double> e = heave.extrema();
  ASSERT_GE(e.size(), 4u);
  const double d = 0.05, expected = archimedes_displacement(heave.liquid_volume), z0 = std::abs(expected);
  const double mean = mean_of_midpoints(e);
  std::printf("floating block, h = 1/120 s: heave about %.5f m against Archimedes %.5f m (%.2f%% of the draft); "
              "first swing %.3f z0\n",
              mean, expected, 100 * std::abs(mean - expected) / d, std::abs(e[0] - expected) / z0);
  EXPECT_NEAR(mean, expected, 0.02 * d);
  for (std::size_t k = 0; k < e.size(); ++k) {
    EXPECT_LE(std::abs(e[k] - expected), z0) << "extremum " << k;
    if (k > 0) {
      EXPECT_LE(std::abs(e[k] - expected), std::abs(e[k - 1] - expected) + 1e-4) << "extremum " << k;
    }
  }
}

TEST(LiquidRun, FloatingBlockStaysStableAtTheLargestStep) {
  // h = 1/30 s (omega h = 0.33): the surface follows the velocity of the step before, an explicit
  // restoring force, and the first swings overshoot z0 (by 36% at most here, measured; 1.7% at
  // 1/60 s and none at 1/120 s); the run must stay finite, keep the Archimedes mean within 2% of the
  // draft, and the energy those swings gained must not keep growing: no swing of the second half
  // of the run is larger than the largest of the first half. (This used to ask for a last swing
  // inside z0: the level set's back-traces that left the fluid were clamped by a walk-dependent
  // projection that damped the heave, to 0.1 z0 by t = 8 s; with the nearest boundary point the
  // swings fall from 1.36 z0 to 1.15 z0 at 3 s and to 0.77 z0 by 8 s, where they stay.)
  const Heave heave = floating_block(1.0 / 30, 3.0, "liquid_floating_block_30");
  const std::vector<double> e = heave.extrema();
  ASSERT_GE(e.size(), 6u);
  const double d = 0.05, expected = archimedes_displacement(heave.liquid_volume);
  EXPECT_NEAR(mean_of_midpoints(e), expected, 0.02 * d);
  double first_half = 0;
  for (std::size_t k = 0; k < e.size() / 2; ++k) first_half = std::max(first_half, std::abs(e[k] - expected));
  for (std::size_t k = e.size() / 2; k < e.size(); ++k)
    EXPECT_LE(std::abs(e[k] - expected), first_half) << "extremum " << k;
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
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_in(dir, scene, &status);
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

// An inflow patch on a wall above a pool (/domain/inflows with a free-surface liquid) pours water:
// after its first step the liquid volume grows at the patch's flow rate Q = U A (1 m/s through
// 0.1 x 0.1 m), measured between 0.1 and 0.3 s; bound 12%: the faces whose centroid lies in the
// patch cover its area only to within about half an edge (0.03 m) along its rim (measured: -7%).
// The tracking drift before the volume restoration stays below 1% every step.
TEST(LiquidRun, InflowPatchPoursLiquidAtItsFlowRate) {
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.3, "dt": 0.01, "frame_rate": 10, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [0, 0, 0], "hi": [0.6, 0.4, 0.3],
               "inflows": [{"lo": [-0.01, 0.2, 0.1], "hi": [0.01, 0.3, 0.2], "velocity": [1, 0, 0]}]},
    "mesh": {"edge_length": 0.03},
    "fluid": {"type": "liquid", "fill": "regions", "regions": [{"type": "below", "height": 0.1}], "viscosity": 0},
    "probes": [{"name": "volume", "kind": "fluid_volume"}]
  })");
  TempDir dir("liquid_inflow");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_in(dir, scene, &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv"), stats = read_csv(out / "stats.csv");
  double v_01 = 0, v_03 = 0;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    if (std::abs(probes.at(r, "time") - 0.1) < 1e-9) v_01 = probes.at(r, "volume");
    if (std::abs(probes.at(r, "time") - 0.3) < 1e-9) v_03 = probes.at(r, "volume");
  }
  const double Q = 1.0 * 0.1 * 0.1, rate = (v_03 - v_01) / 0.2;
  std::printf("inflow patch into a pool: volume %.5f -> %.5f m^3 from 0.1 to 0.3 s, rate %.5f m^3/s (U A = %.5f)\n",
              v_01, v_03, rate, Q);
  EXPECT_NEAR(rate, Q, 0.12 * Q);
  for (std::size_t r = 0; r < stats.rows.size(); ++r) EXPECT_LT(std::abs(stats.at(r, "volume_drift")), 0.01) << "step " << r + 1;
}

TEST(LiquidRun, PaintPourFallsOnTheSoftBallAndKeepsItsSurfaceClosed) {
  // paint_pour_ci.json: the nozzle pours onto a soft ball held at its base (coupled, eq. 7). The
  // liquid volume never falls while the nozzle is on, every frame's liquid surface (the solver's
  // own, export.liquid_surface "tets") is closed and encloses the liquid volume, and the ball's top
  // moves down (its weight and the liquid's).
  TempDir dir("liquid_paint_pour");
  const fs::path out = dir.path() / "out";
  json scene = committed("paint_pour_ci.json");
  scene["export"]["liquid_surface"] = json::parse(R"({"type": "tets"})");
  int status = -1;
  const std::string log = run_in(dir, scene, &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv");
  for (std::size_t r = 1; r < probes.rows.size(); ++r)
    EXPECT_GE(probes.at(r, "liquid_volume"), probes.at(r - 1, "liquid_volume") * (1 - 1e-12)) << "row " << r;
  EXPECT_GT(probes.at(probes.rows.size() - 1, "liquid_volume"), probes.at(0, "liquid_volume"));
  EXPECT_LT(probes.at(probes.rows.size() - 1, "ball_top_y"), 0.0);
  for (int frame = 0; frame <= 9; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "liquid_%05d.ply", frame);
    const auto ply = read_ply(out / "surfaces" / name);
    EXPECT_EQ(open_edges(ply), 0) << "frame " << frame;
    // The frame at t = frame / 30 s is the probes row at that time.
    double volume = -1;
    for (std::size_t r = 0; r < probes.rows.size(); ++r)
      if (std::abs(probes.at(r, "time") - frame / 30.0) < 1e-9) volume = probes.at(r, "liquid_volume");
    ASSERT_GT(volume, 0) << "frame " << frame;
    // The surface is drawn on the fluid nodes moved with the ball to the frame's time (frames in
    // step, apps/run/README.md), the liquid volume on the mesh the step ran on: the surface
    // encloses the liquid of its own frame's grid (float32 coordinates: 1e-5), which differs from
    // the conserved volume by what the step's mesh motion did to the wet tets.
    char grid[32];
    std::snprintf(grid, sizeof grid, "fluid_%05d.vtu", frame);
    const double drawn = grid_liquid_volume(out / "fluid" / grid);
    EXPECT_NEAR(enclosed_volume(ply), drawn, 1e-5 * volume) << "frame " << frame;
    std::printf("frame %d: surface encloses %.9g m^3, its grid %.9g, conserved %.9g (%+.2e)\n", frame,
                enclosed_volume(ply), drawn, volume, drawn / volume - 1);
  }
}

TEST(LiquidRun, MeshIsFinerAtTheSurfaceAndFollowsIt) {
  // dam_break_ci.json with fluid.surface_edge_length 0.04 m (half the mesh's 0.08 m), the post
  // fixed (fluid runner) and deforming (coupled runner, eq. 7): the fluid is remeshed as the
  // surface moves (at least twice in 0.3 s), each time only part of it (where the mesh no longer
  // fits the sizing field), with the volume kept to 1e-9 through every remesh; the surface
  // triangles are finer than on the uniform 0.08 m mesh, and the mesh has fewer than half the
  // tets of the uniform mesh at the surface's size (dam_break.json, 0.04 m).
  const Eigen::Vector3d lo(0, 0, 0), hi(1.6, 0.8, 0.4);
  auto run = [](const json& scene, const std::string& name, double end_time, Csv* stats, Csv* probes,
                std::vector<PlyData>* surfaces) {
    TempDir dir(name);
    const fs::path file = dir.path() / "scene.json", out = dir.path() / "out";
    std::ofstream(file) << scene.dump(2);
    int status = -1;
    const std::string log = tetfsi_cmd("run " + file.string() + " --out " + out.string() + " --quiet --threads 1 " +
                                           "--end-time " + std::to_string(end_time),
                                       &status);
    ASSERT_EQ(status, 0) << log;
    *stats = read_csv(out / "stats.csv");
    if (probes) *probes = read_csv(out / "probes.csv");
    if (surfaces)
      for (int frame = 0; frame <= 6; ++frame) {
        char n[32];
        std::snprintf(n, sizeof n, "liquid_%05d.ply", frame);
        surfaces->push_back(read_ply(out / "surfaces" / n));
      }
  };
  // The post as a fixed obstacle (a zero translation): the fluid runner, which remeshes for the surface.
  auto rigid_post = [](json scene) {
    scene["solids"][0].erase("fixed_regions");
    scene["solids"][0]["motion"] = json::parse(R"({"type": "translation", "velocity": [0, 0, 0]})");
    scene.erase("coupling");
    json probes = json::array();
    for (const auto& p : scene["probes"])
      if (p["kind"] != "point_displacement") probes.push_back(p);
    scene["probes"] = probes;
    return scene;
  };
  // The solver's own surface (export.liquid_surface "tets"): its triangles are the cut tets' facets.
  auto tets_surface = [](json scene) {
    scene["export"]["liquid_surface"] = json::parse(R"({"type": "tets"})");
    return scene;
  };
  json adaptive = tets_surface(rigid_post(committed("dam_break_ci.json")));
  adaptive["fluid"]["surface_edge_length"] = 0.04;
  Csv stats, probes, uniform_stats, fine_stats;
  std::vector<PlyData> surfaces, uniform_surfaces;
  run(adaptive, "liquid_adaptive", 0.3, &stats, &probes, &surfaces);
  run(tets_surface(rigid_post(committed("dam_break_ci.json"))), "liquid_uniform", 0.3, &uniform_stats, nullptr,
      &uniform_surfaces);
  run(rigid_post(committed("dam_break.json")), "liquid_uniform_fine", 0.01, &fine_stats, nullptr, nullptr);
  const auto check = [&](const Csv& stats, const Csv& probes, const std::vector<PlyData>& surfaces,
                         const char* tets_column) {
    ASSERT_FALSE(stats.rows.empty());
    const double v0 = probes.at(0, "liquid_volume");
    double remeshes = 0, max_tets = 0;
    for (std::size_t r = 0; r < stats.rows.size(); ++r) {
      remeshes += stats.at(r, "remeshed");
      max_tets = std::max(max_tets, stats.at(r, tets_column));
      EXPECT_NEAR(stats.at(r, "liquid_volume"), v0, 1e-9 * v0) << "step " << r + 1;
    }
    EXPECT_GE(remeshes, 2.0);
    EXPECT_LT(max_tets, 0.5 * fine_stats.at(0, "tets"));
    for (std::size_t frame = 1; frame < surfaces.size(); ++frame) {
      EXPECT_EQ(open_edges(surfaces[frame]), 0) << "frame " << frame;
      EXPECT_NEAR(enclosed_volume(surfaces[frame]), v0, 1e-5 * v0) << "frame " << frame;
      EXPECT_LT(mean_free_edge(surfaces[frame], lo, hi), mean_free_edge(uniform_surfaces[frame], lo, hi))
          << "frame " << frame;
    }
  };
  {
    SCOPED_TRACE("fluid runner");
    check(stats, probes, surfaces, "tets");
    const double U = std::sqrt(2 * 9.81 * 0.6), h = 0.04;
    for (std::size_t r = 0; r < stats.rows.size(); ++r) {
      EXPECT_LE(stats.at(r, "max_divergence"), 1e-8 * U / h) << "step " << r + 1;
      // A local remesh, not the whole fluid (the fallback when the region to refit is not a ball
      // hands CGAL every tet). Measured: at most 77% of the tets, and 81% since the level set's
      // traces that leave the fluid are clamped to the nearest boundary point (the refits come one
      // step earlier, and the third finds the surface farther from the second).
      if (stats.at(r, "remeshed") > 0) {
        EXPECT_LT(stats.at(r, "remeshed_tets"), stats.at(r, "tets")) << "step " << r + 1;
      }
    }
  }
  json coupled = tets_surface(committed("dam_break_ci.json"));
  coupled["fluid"]["surface_edge_length"] = 0.04;
  Csv coupled_stats, coupled_probes;
  std::vector<PlyData> coupled_surfaces;
  run(coupled, "liquid_adaptive_coupled", 0.3, &coupled_stats, &coupled_probes, &coupled_surfaces);
  {
    SCOPED_TRACE("coupled runner");
    check(coupled_stats, coupled_probes, coupled_surfaces, "fluid_tets");
  }
}

TEST(LiquidRun, BadFreeSurfaceKeysExitTwoInValidateAndRunAlike) {
  // Each case: a change to dam_break_ci.json (or floating_block_ci.json) and the JSON pointer the
  // message must name. validate and run give exit 2 and name it.
  struct Case {
    const char* scene;
    const char* patch;  // JSON merge patch
    const char* pointer;
  };
  const Case cases[] = {
      {"dam_break_ci.json", R"({"fluid": {"regions": []}})", "/fluid/regions"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "box", "lo": [5, 5, 5], "hi": [6, 6, 6]}]}})",
       "/fluid/regions"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "sphere", "center": [9, 9, 9], "radius": 1}]}})",
       "/fluid/regions"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "below", "height": -1}]}})", "/fluid/regions"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]}})",
       "/fluid/regions/0/radius"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "cone"}]}})", "/fluid/regions/0/type"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "box", "lo": [1, 1, 1], "hi": [0, 0, 0]}]}})",
       "/fluid/regions/0/hi"},
      {"dam_break_ci.json", R"({"fluid": {"surface_edge_length": 0.5}})", "/fluid/surface_edge_length"},
      {"dam_break_ci.json", R"({"fluid": {"surface_edge_length": -0.01}})", "/fluid/surface_edge_length"},
      {"dam_break_ci.json", R"({"fluid": {"fill": "domain", "surface_edge_length": 0.04}})",
       "/fluid/surface_edge_length"},
      {"dam_break_ci.json", R"({"fluid": {"fill": "puddle"}})", "/fluid/fill"},
      {"floating_block_ci.json", R"({"solids": [{"name": "liquid", "geometry": {"type": "box", "size": [0.2, 0.1, 0.2]},
          "material": {"density": 500, "youngs_modulus": 1e6, "poissons_ratio": 0.3},
          "placement": {"translation": [0, 0.27, 0]}}], "probes": []})",
       "/solids/0/name"},
      {"floating_block_ci.json", R"({"coupling": {"constraint": "step_mean"}})", "/coupling/constraint"},
      {"floating_block_ci.json", R"({"fluid": {"surface_edge_length": 0.08}})", "/fluid/surface_edge_length"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "mesh", "file": "missing.obj"}]}})",
       "/fluid/regions/0/file"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "mesh", "file": "open.obj"}]}})",
       "/fluid/regions/0/file"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "mesh", "file": "cube.obj", "translation": [9, 9, 9]}]}})",
       "/fluid/regions/0: the region lies outside the domain box"},
      {"dam_break_ci.json", R"({"fluid": {"regions": [{"type": "mesh", "file": "cube.obj", "unit_scale": 0}]}})",
       "/fluid/regions/0/unit_scale"},
      // Velocity on particles: a count beyond memory, and values out of range.
      {"dam_break_ci.json", R"({"fluid": {"advection": "apic", "particles_per_tet": 1000000000}})",
       "/fluid/particles_per_tet"},
      {"dam_break_ci.json", R"({"fluid": {"advection": "flip", "particles_per_tet": 0}})", "/fluid/particles_per_tet"},
      {"dam_break_ci.json", R"({"fluid": {"advection": "flip", "flip_ratio": 1.5}})", "/fluid/flip_ratio"},
      {"dam_break_ci.json", R"({"fluid": {"advection": "apick"}})", "/fluid/advection"},
  };
  TempDir dir("liquid_bad_keys");
  std::ofstream(dir.path() / "open.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\n";
  write_box_obj(dir.path() / "cube.obj", Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Vector3d(0.3, 0.3, 0.3));
  int index = 0;
  for (const Case& c : cases) {
    json scene = committed(c.scene);
    scene.merge_patch(json::parse(c.patch));
    const fs::path file = dir.path() / ("bad_" + std::to_string(index++) + ".json");
    std::ofstream(file) << scene.dump(2);
    int validate_status = -1, run_status = -1;
    const std::string validate = tetfsi_cmd("validate " + file.string(), &validate_status);
    const std::string run = tetfsi_cmd("run " + file.string() + " --out " + (dir.path() / "out").string() +
                                           " --quiet --end-time 0.02",
                                       &run_status);
    EXPECT_EQ(validate_status, 2) << c.patch << "\n" << validate;
    EXPECT_EQ(run_status, 2) << c.patch << "\n" << run;
    EXPECT_NE(validate.find(c.pointer), std::string::npos) << c.patch << "\n" << validate;
    EXPECT_NE(run.find(c.pointer), std::string::npos) << c.patch << "\n" << run;
  }
}

TEST(LiquidRun, TimeSplittingFailsOnTheLightFloatingBlockOnly) {
  // The time-splitting baseline on the same free-surface scene (floating_block_ci.json, h = 1/120 s,
  // 0.5 s): with the block at half the water's density its heave added mass exceeds its mass and
  // the partitioned scheme diverges (the run stops with exit 1; the simultaneous solve is stable
  // on it, FloatingBlockHeavesAboutTheArchimedesDraft); at 900 kg/m^3 it runs through.
  TempDir dir("liquid_splitting");
  auto run = [&](double density, double y0, const std::string& name) {
    json scene = committed("floating_block_ci.json");
    scene["coupling"]["scheme"] = "time_splitting";
    scene["simulation"]["end_time"] = 0.5;
    scene["solids"][0]["material"]["density"] = density;
    scene["solids"][0]["placement"]["translation"] = {0, y0, 0};
    const fs::path file = dir.path() / (name + ".json");
    std::ofstream(file) << scene.dump(2);
    int status = -1;
    const std::string log =
        tetfsi_cmd("run " + file.string() + " --out " + (dir.path() / name).string() + " --quiet --threads 1", &status);
    return std::make_pair(status, log);
  };
  const auto light = run(500, 0.27, "light");
  EXPECT_EQ(light.first, 1) << light.second;
  EXPECT_NE(light.second.find("time_splitting"), std::string::npos) << light.second;
  const auto heavy = run(900, 0.23, "heavy");
  EXPECT_EQ(heavy.first, 0) << heavy.second;
}

TEST(LiquidRun, CappedSphereRegionHoldsTheCapVolume) {
  // A sphere of radius R = 0.3 m cut at a height h = 0.2 m above its bottom: V = π h² (3R − h) / 3
  // (the part of a bowl filled to a level). The P1 level set's volume before any step (the target
  // the run then keeps) converges to it at second order; the cap's sharp rim costs more than a
  // whole sphere does (-1.4% and -0.35% at the same sizes). Seen: -5.0% at edge 0.04 m, -1.3% at 0.02 m.
  const double R = 0.3, h = 0.2, exact = std::acos(-1.0) * h * h * (3 * R - h) / 3;
  std::vector<double> error;
  for (const double edge : {0.04, 0.02}) {
    json scene = committed("dam_break_ci.json");
    scene.erase("solids");
    scene["probes"] = json::array({{{"name", "liquid_volume"}, {"kind", "fluid_volume"}}});
    scene["simulation"]["end_time"] = 0.01;
    scene["domain"] = {{"lo", {0, 0, 0}}, {"hi", {0.8, 0.8, 0.8}}};
    scene["mesh"]["edge_length"] = edge;
    scene["mesh"]["edge_length_near_solids"] = edge;
    scene["fluid"]["regions"] = json::array({{{"type", "sphere"}, {"center", {0.4, 0.4, 0.4}}, {"radius", R},
                                              {"cap_height", 0.4 - R + h}}});
    TempDir dir("liquid_cap");
    std::ofstream(dir.path() / "cap.json") << scene.dump(2);
    int status = -1;
    const std::string log = tetfsi_cmd("run " + (dir.path() / "cap.json").string() + " --out " +
                                           (dir.path() / "out").string() + " --quiet", &status);
    ASSERT_EQ(status, 0) << log;
    const Csv probes = read_csv(dir.path() / "out" / "probes.csv");
    error.push_back(probes.at(0, "liquid_volume") / exact - 1);
    std::printf("capped sphere, edge %.2f m: liquid volume %.5f m^3 against the cap's %.5f m^3 (%+.2f%%)\n", edge,
                probes.at(0, "liquid_volume"), exact, 100 * error.back());
  }
  EXPECT_GT(std::abs(error[0]) / std::abs(error[1]), 3.0);  // second order: 4
  EXPECT_LT(std::abs(error[1]), 0.02);
}
