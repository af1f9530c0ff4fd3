// The liquid surface written for renderers (export.liquid_surface, fluid/io/render_surface.hpp),
// through `tetfsi run`:
//  - a still pool (fluid runner, CGAL mesh, 0.1 s): every frame's surface is closed, its top flat
//    to 1% of the mesh edge length at the still height, spanning the tank wall to wall, its volume
//    the liquid's, its vertex velocities zero;
//  - the falling bowl (bowl_drop_ci.json, 0.1 s, before the impact): no tet-scale spikes. Measure:
//    the angle between the normals of every two triangles that share an edge, on the free surface
//    (edges more than 5 cm from the bowl and the tank's walls, where the liquid ends on them with a
//    sharp edge on purpose). Bound: 0.5 rad (29 deg). Neighbouring triangles of the smooth surface
//    lie about a voxel h = sigma / 4 apart (a quad's two triangles closer), and a surface smoothed
//    at sigma keeps no bend of radius much below sigma, so they differ by about h / sigma = 0.25 rad;
//    the bound leaves a factor 2 for the split of the mesher's quads (each quad's two triangles
//    fold along its diagonal). The marching-tets surface of the same run ("tets") exceeds it: its
//    facets meet at the kinks of the P1 level set (checked, so that the measure can fail). The
//    water in the falling bowl moves at the bowl's free-fall speed: the vertex velocities there are
//    -g t, on average within 2%, each within 10%.
//  - the same run on to 0.25 s, through the impact (0.24 s): every frame's smooth surface encloses
//    the simulated liquid's volume (the fluid_volume probe) to 0.5% (issue 41's bound), although the
//    frame draws the level set on the nodes moved with the bowl, where it holds up to 4% less.
//  - bad values of the keys give exit 2 naming them, in validate and run alike.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "csv.hpp"
#include "ply_reader.hpp"
#include "tests/fluid/surface_checks.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;
namespace checks = tetfsi::fluid::testing;

namespace {

/// Runs `scene` into dir/name on one thread (extra arguments appended); returns the output folder.
fs::path run_scene(const TempDir& dir, const std::string& name, const json& scene, const std::string& extra = "") {
  const fs::path file = dir.path() / (name + ".json"), out = dir.path() / name;
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string log =
      tetfsi_cmd("run " + file.string() + " --out " + out.string() + " --quiet --threads 1 " + extra, &status);
  EXPECT_EQ(status, 0) << log;
  return out;
}

PlyData frame(const fs::path& out, const std::string& object, int k) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%05d.ply", object.c_str(), k);
  return read_ply(out / "surfaces" / name);
}

/// The PLY's positions and triangles as a surface (surface_checks.hpp reads those).
tetfsi::mesh::SurfaceMesh surface(const PlyData& p) {
  tetfsi::mesh::SurfaceMesh s;
  s.vertices = p.positions;
  s.triangles = p.triangles;
  return s;
}

/// Distance from x to triangle (a, b, c): the nearest of its plane's foot (if inside) and its edges.
double triangle_distance(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c) {
  auto segment = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    const double t = std::clamp((x - p).dot(q - p) / (q - p).squaredNorm(), 0.0, 1.0);
    return (p + t * (q - p) - x).norm();
  };
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d foot = x - n * n.dot(x - a);
  const double s1 = n.dot((b - a).cross(foot - a)), s2 = n.dot((c - b).cross(foot - b)), s3 = n.dot((a - c).cross(foot - c));
  if (s1 >= 0 && s2 >= 0 && s3 >= 0) return std::abs(n.dot(x - a));
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

/// The largest angle between the normals of two triangles sharing an edge [rad], over the edges
/// whose midpoint is farther than `margin` from the box [lo, hi]'s faces and from `solid`.
double largest_bend(const PlyData& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const PlyData& solid,
                    double margin) {
  double worst = 0;
  for (const auto& b : checks::bends(surface(p))) {
    if (((b.where - lo).array() < margin).any() || ((hi - b.where).array() < margin).any()) continue;
    bool near_solid = false;
    for (const auto& t : solid.triangles)
      if (triangle_distance(b.where, solid.positions[t[0]], solid.positions[t[1]], solid.positions[t[2]]) < margin) {
        near_solid = true;
        break;
      }
    if (!near_solid) worst = std::max(worst, b.angle_deg * M_PI / 180);
  }
  return worst;
}

TEST(LiquidSurfaceExport, StillPoolIsFlatToOnePercentOfTheEdgeWallToWall) {
  const double edge = 0.05, H = 0.17;
  const json scene = json::parse(R"({
    "simulation": {"end_time": 0.1, "dt": 0.025, "frame_rate": 20, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [0, 0, 0], "hi": [0.6, 0.4, 0.3]},
    "mesh": {"edge_length": 0.05},
    "fluid": {"type": "liquid", "density": 1000, "viscosity": 0, "fill": "regions",
              "regions": [{"type": "below", "height": 0.17}], "solver": {"type": "amg", "tolerance": 1e-10}},
    "probes": [{"name": "liquid_volume", "kind": "fluid_volume"}],
    "export": {"vtu": false, "surfaces": "ply"}})");
  TempDir dir("surface_still_pool");
  const fs::path out = run_scene(dir, "pool", scene);
  const Csv probes = read_csv(out / "probes.csv");
  for (int k = 0; k <= 2; ++k) {
    const PlyData p = frame(out, "liquid", k);
    const tetfsi::mesh::SurfaceMesh sm = surface(p);
    ASSERT_FALSE(p.triangles.empty());
    ASSERT_EQ(p.velocities.size(), p.positions.size());
    EXPECT_EQ(checks::open_or_nonmanifold_edges(sm), 0) << "frame " << k;
    const double volume = probes.at(0, "liquid_volume");  // kept to 1e-9 by the solver
    EXPECT_NEAR(checks::enclosed_volume(sm), volume, 5e-3 * volume) << "frame " << k;
    double top_area = 0, worst = 0, speed = 0;
    for (const auto& t : p.triangles) {
      const Eigen::Vector3d a = checks::area_vector(sm, t);
      if (a.normalized().y() < 0.5) continue;  // the top: triangles facing up
      top_area += a.norm();
      for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(p.positions[t[i]].y() - H));
    }
    for (const auto& u : p.velocities) speed = std::max(speed, u.norm());
    std::printf("still pool, frame %d: top flat to %.2e of the edge, area %.6f m^2, volume %+.2e, max |u| %.2e m/s\n",
                k, worst / edge, top_area, checks::enclosed_volume(sm) / volume - 1, speed);
    EXPECT_LT(worst, 0.01 * edge) << "frame " << k;
    EXPECT_NEAR(top_area, 0.6 * 0.3, 1e-4) << "frame " << k;  // wall to wall (float coordinates)
    EXPECT_LT(speed, 1e-6) << "frame " << k;
  }
}

TEST(LiquidSurfaceExport, FallingBowlHasNoTetScaleSpikesAndFallsAtGravity) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.8, 0.75, 0.8);
  const double bound = 0.5, g = 9.81;
  TempDir dir("surface_falling_bowl");
  json smooth = committed("bowl_drop_ci.json");
  smooth["export"]["vtu"] = false;
  json tets = smooth;
  tets["export"]["liquid_surface"] = json::parse(R"({"type": "tets"})");
  const fs::path out_smooth = run_scene(dir, "smooth", smooth, "--end-time 0.25");
  const fs::path out_tets = run_scene(dir, "tets", tets, "--end-time 0.1");
  double worst_smooth = 0, worst_tets = 0;
  for (int k = 1; k <= 6; ++k) {  // 1/60 .. 0.1 s: the bowl falls freely (impact at about 0.24 s)
    const PlyData s = frame(out_smooth, "liquid", k), t = frame(out_tets, "liquid", k);
    EXPECT_EQ(checks::open_or_nonmanifold_edges(surface(s)), 0) << "frame " << k;
    const double bend_smooth = largest_bend(s, lo, hi, frame(out_smooth, "bowl", k), 0.05);
    const double bend_tets = largest_bend(t, lo, hi, frame(out_tets, "bowl", k), 0.05);
    std::printf("falling bowl, frame %d: largest bend %.1f deg smooth, %.1f deg tets\n", k, bend_smooth * 180 / M_PI,
                bend_tets * 180 / M_PI);
    EXPECT_LT(bend_smooth, bound) << "frame " << k;
    worst_smooth = std::max(worst_smooth, bend_smooth);
    worst_tets = std::max(worst_tets, bend_tets);
    // The water in the bowl (above y = 0.2 m; the pool is below 0.08 m) falls with it at -g t:
    // on average to 2% (the solver keeps it to 0.13%, test_liquid_falling_bowl.cpp), each vertex
    // to 10% (node averages at the surface mix in the air's extended velocity).
    const double t_frame = k / 60.0;
    double vy = 0;
    int n = 0;
    for (std::size_t v = 0; v < s.positions.size(); ++v)
      if (s.positions[v].y() > 0.2) {
        vy += s.velocities[v].y(), ++n;
        EXPECT_NEAR(s.velocities[v].y(), -g * t_frame, 0.1 * g * t_frame) << "frame " << k << ", vertex " << v;
      }
    ASSERT_GT(n, 0) << "frame " << k;
    EXPECT_NEAR(vy / n, -g * t_frame, 0.02 * g * t_frame) << "frame " << k;
  }
  EXPECT_GT(worst_tets, bound);  // the measure fails the marching-tets surface of the same run
  const Csv probes = read_csv(out_smooth / "probes.csv");
  for (int k = 0; k <= 15; ++k) {  // 0 .. 0.25 s, the last frames in the impact
    const double volume = probes.at(0, "liquid_volume");  // kept to 1e-9 by the solver
    const double enclosed = checks::enclosed_volume(surface(frame(out_smooth, "liquid", k)));
    std::printf("falling bowl, frame %d: enclosed volume %+.2e of the liquid's\n", k, enclosed / volume - 1);
    EXPECT_NEAR(enclosed, volume, 5e-3 * volume) << "frame " << k;
  }
}

TEST(LiquidSurfaceExport, BadKeysExitTwoInValidateAndRunAlike) {
  struct Case {
    const char* patch;  // JSON merge patch on dam_break_ci.json
    const char* pointer;
  };
  const Case cases[] = {
      {R"({"export": {"liquid_surface": {"type": "marching"}}})", "/export/liquid_surface/type"},
      {R"({"export": {"liquid_surface": {"voxel_size": 0}}})", "/export/liquid_surface/voxel_size"},
      {R"({"export": {"liquid_surface": {"smoothing": -0.1}}})", "/export/liquid_surface/smoothing"},
      {R"({"export": {"liquid_surface": {"voxel_size": 0.01, "smoothing": 0.5}}})", "/export/liquid_surface/smoothing"},
      {R"({"export": {"liquid_surface": {"type": "tets", "voxel_size": 0.01}}})", "/export/liquid_surface/voxel_size"},
      {R"({"export": {"liquid_surface": {"voxel_size": 1e-5}}})", "/export/liquid_surface/voxel_size"},
      {R"({"export": {"liquid_surface": {"smothing": 0.1}}})", "/export/liquid_surface/smothing"},
  };
  TempDir dir("surface_bad_keys");
  int index = 0;
  for (const Case& c : cases) {
    json scene = committed("dam_break_ci.json");
    scene.merge_patch(json::parse(c.patch));
    const fs::path file = dir.path() / ("bad_" + std::to_string(index++) + ".json");
    std::ofstream(file) << scene.dump(2);
    int validate_status = -1, run_status = -1;
    const std::string validate = tetfsi_cmd("validate " + file.string(), &validate_status);
    const std::string run = tetfsi_cmd(
        "run " + file.string() + " --out " + (dir.path() / "out").string() + " --quiet --end-time 0.02", &run_status);
    EXPECT_EQ(validate_status, 2) << c.patch << "\n" << validate;
    EXPECT_EQ(run_status, 2) << c.patch << "\n" << run;
    EXPECT_NE(validate.find(c.pointer), std::string::npos) << c.patch << "\n" << validate;
    EXPECT_NE(run.find(c.pointer), std::string::npos) << c.patch << "\n" << run;
  }
}

}  // namespace
