// A liquid carried by a falling solid (tetfsi issue 15), through `tetfsi run`: a soft bowl
// (geometry.type bowl, R = 0.2 m, wall 4 cm) holding water (a sphere region with a cap height) in
// free fall, coupled through eq. (7) of Chentanez et al. 2006 with a free surface, at h = 1/240 s.
// In free fall nothing but gravity acts: bowl and water fall together at -g t, the pressure stays
// at zero and the water stays where it is in the bowl. Checked every frame (60 Hz, 0.1 s):
//  - the water's mean velocity (liquid volume weighted) is -g t within 2%;
//  - the bowl's mean velocity is -g t within 2%;
//  - at least 99% of the water is inside the bowl (its inner sphere below the rim, moved with it).
// Before the interface map took the pressure on the wet part of cut interface triangles only
// (fluid::wet_face_mass), the water fell 11% faster than -g t by 0.07 s and the bowl 5.7%
// slower (the pressure sucked the water into the wall and the wall up). Printed, not checked: the
// level set's drift per step before the restoration (stats.csv volume_drift; -1.7% per step before
// the redistancing kept the cut tets and continued the surface across walls, now +0.03%).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

constexpr double kG = 9.81, kRadius = 0.2, kThickness = 0.04;
const Eigen::Vector3d kBowlCentre(0.4, 0.5, 0.4);  // its spheres' centre; the rim is the plane y = 0.5

json falling_bowl_scene() {
  return json::parse(R"({
    "simulation": {"end_time": 0.1, "frame_rate": 60, "dt": 0.004166666666666667, "gravity": [0, -9.81, 0]},
    "domain": {"lo": [0, 0, 0], "hi": [0.8, 0.7, 0.8]},
    "mesh": {"edge_length": 0.08, "edge_length_near_solids": 0.03, "grading_distance": 0.1},
    "fluid": {"type": "liquid", "density": 1000, "fill": "regions",
              "regions": [{"type": "sphere", "center": [0.4, 0.5, 0.4], "radius": 0.15, "cap_height": 0.45}],
              "solver": {"type": "amg", "tolerance": 1e-8}, "level_set_advection": "bfecc"},
    "solids": [{"name": "bowl",
                "geometry": {"type": "bowl", "radius": 0.2, "thickness": 0.04, "segments": 24, "rings": 6},
                "material": {"density": 1100, "youngs_modulus": 1e5, "poissons_ratio": 0.4,
                             "constitutive": "neohookean", "rayleigh_beta": 0.005},
                "placement": {"translation": [0.4, 0.5, 0.4]}}],
    "export": {"vtu": true}
  })");
}

const mesh::io::DataArray& field(const std::vector<mesh::io::DataArray>& fields, const std::string& name) {
  for (const auto& f : fields)
    if (f.name == name) return f;
  throw std::runtime_error("no field " + name);
}

Eigen::Vector3d vec(const mesh::io::DataArray& f, int i) {
  return Eigen::Vector3d(f.values[3 * i], f.values[3 * i + 1], f.values[3 * i + 2]);
}

/// The liquid of one fluid frame: its volume, its volume inside the bowl (tet centroids within
/// the inner sphere about `centre`, and below the rim) and its mean velocity.
struct Liquid {
  double volume = 0, inside = 0;
  Eigen::Vector3d mean_velocity = Eigen::Vector3d::Zero();
};

Liquid liquid_of(const mesh::io::UnstructuredGrid& g, const Eigen::Vector3d& centre) {
  const auto& fraction = field(g.cell_data, "liquid_fraction");
  const auto& velocity = field(g.cell_data, "velocity");
  Liquid l;
  for (int c = 0; c < g.num_cells(); ++c) {
    const std::int64_t* v = &g.connectivity[g.offsets[c] - 4];
    const Eigen::Vector3d &a = g.points[v[0]], &b = g.points[v[1]], &d = g.points[v[2]], &e = g.points[v[3]];
    const double w = fraction.values[c] * std::abs((b - a).cross(d - a).dot(e - a)) / 6.0;
    const Eigen::Vector3d centroid = (a + b + d + e) / 4.0;
    l.volume += w;
    l.mean_velocity += w * vec(velocity, c);
    if ((centroid - centre).norm() < kRadius - kThickness && centroid.y() < centre.y()) l.inside += w;
  }
  l.mean_velocity /= l.volume;
  return l;
}

}  // namespace

TEST(LiquidFallingBowl, WaterFallsWithTheBowlAndStaysInIt) {
  TempDir dir("liquid_falling_bowl");
  std::ofstream(dir.path() / "bowl.json") << falling_bowl_scene().dump(2);
  int status = -1;
  const fs::path out = dir.path() / "out";
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + (dir.path() / "bowl.json").string() +
                                          " --out " + out.string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << log;
  const int frames = 7;  // 0 .. 0.1 s at 60 Hz
  const auto bowl0 = mesh::io::read_vtu(out / "bowl" / "bowl_00000.vtu");
  const double inside0 = liquid_of(mesh::io::read_vtu(out / "fluid" / "fluid_00000.vtu"), kBowlCentre).inside;
  for (int k = 1; k < frames; ++k) {
    const double t = k / 60.0;
    const auto bowl = mesh::io::read_vtu(out / "bowl" / fmt::format("bowl_{:05d}.vtu", k));
    Eigen::Vector3d shift = Eigen::Vector3d::Zero(), bowl_velocity = Eigen::Vector3d::Zero();
    const auto& u = field(bowl.point_data, "velocity");
    for (int i = 0; i < bowl.num_points(); ++i) {
      shift += bowl.points[i] - bowl0.points[i];
      bowl_velocity += vec(u, i);
    }
    shift /= bowl.num_points();
    bowl_velocity /= bowl.num_points();
    const Liquid l = liquid_of(mesh::io::read_vtu(out / "fluid" / fmt::format("fluid_{:05d}.vtu", k)), kBowlCentre + shift);
    std::printf("t = %.4f s: water vy %.4f, bowl vy %.4f m/s against -g t = %.4f; water in the bowl %.4f of t = 0\n",
                t, l.mean_velocity.y(), bowl_velocity.y(), -kG * t, l.inside / inside0);
    EXPECT_NEAR(l.mean_velocity.y() / (-kG * t), 1.0, 0.02) << "t = " << t;
    EXPECT_NEAR(bowl_velocity.y() / (-kG * t), 1.0, 0.02) << "t = " << t;
    EXPECT_GT(l.inside / inside0, 0.99) << "t = " << t;
  }
  // The first steps settle the sampled level set.
  const Csv stats = read_csv(out / "stats.csv");
  double drift = 0;
  for (std::size_t r = 3; r < stats.rows.size(); ++r) drift += stats.at(r, "volume_drift") / (stats.rows.size() - 3);
  std::printf("mean volume drift of a step from step 4 on, before the restoration: %+.4f (not checked)\n", drift);
}

/// Mean displacement of a bowl frame's points from the first frame's [m].
static Eigen::Vector3d mean_shift(const mesh::io::UnstructuredGrid& bowl, const mesh::io::UnstructuredGrid& bowl0) {
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (int i = 0; i < bowl.num_points(); ++i) shift += bowl.points[i] - bowl0.points[i];
  return shift / bowl.num_points();
}

// data/scenes/bowl_drop_ci.json (Chentanez et al. 2006, Fig. 5, CI size), through `tetfsi run`: the
// soft bowl full of water (rim at y = 0.55 m, 11 cm of water) falls 0.27 m onto a tank with 8 cm
// of water and hits the floor (wall contact inside the coupled solve).
// Checked: the run ends (exit 0) with finite energies; the liquid volume is kept to 1e-9 every
// step and the tracking drift before the restoration stays small (bounds below, as measured);
// the bowl's lowest point comes within 4 cm of the floor (it starts 0.35 m above it); the water in
// the bowl does not pass through its wall on impact (at least 90% of it is still inside at 0.4 s).
// Not checked: the splash over the rim of the paper's figure. At this size (3 cm edge near the
// bowl) the water rises to the rim (0.003 m above it at 0.4 s, 0.08 L of 11 L) but does not
// leave; the 0.78 measured before the nearest-point clamp of back-traces (fluid/README.md) was
// water lost through the wall, not a splash.
TEST(LiquidFallingBowl, BowlDropHitsTheFloorKeepingTheWaterInTheBowl) {
  TempDir dir("bowl_drop");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + std::string(TETFSI_SOURCE_DIR) +
                                          "/data/scenes/bowl_drop_ci.json --out " + out.string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << log;
  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_GT(stats.rows.size(), 90u);
  const double v0 = stats.at(0, "liquid_volume");
  double mean_drift = 0, worst_drift = 0;
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_TRUE(std::isfinite(stats.at(r, "total_energy"))) << "step " << r + 1;
    EXPECT_NEAR(stats.at(r, "liquid_volume"), v0, 1e-9 * v0) << "step " << r + 1;
    if (r < 3) continue;  // the first steps settle the sampled level set
    mean_drift += std::abs(stats.at(r, "volume_drift")) / (stats.rows.size() - 3);
    worst_drift = std::max(worst_drift, std::abs(stats.at(r, "volume_drift")));
  }
  const int last = 24;  // 0.4 s at 60 Hz
  const auto bowl0 = mesh::io::read_vtu(out / "bowl" / "bowl_00000.vtu");
  const auto bowl = mesh::io::read_vtu(out / "bowl" / fmt::format("bowl_{:05d}.vtu", last));
  double lowest = 1e9;
  for (const auto& x : bowl.points) lowest = std::min(lowest, x.y());
  const Eigen::Vector3d centre0(0.4, 0.55, 0.4);
  const double inside0 = liquid_of(mesh::io::read_vtu(out / "fluid" / "fluid_00000.vtu"), centre0).inside;
  const double inside = liquid_of(mesh::io::read_vtu(out / "fluid" / fmt::format("fluid_{:05d}.vtu", last)),
                                  centre0 + mean_shift(bowl, bowl0))
                            .inside;
  std::printf("bowl drop (CI): %zu steps, mean |volume drift| per step %.4f, worst %.4f; bowl's lowest point "
              "%.4f m; water inside the bowl at 0.4 s: %.3f of the start\n",
              stats.rows.size(), mean_drift, worst_drift, lowest, inside / inside0);
  EXPECT_LE(mean_drift, 0.003);  // measured 0.0018 (3e-4 per step in the fall, up to 2.2% at the impact)
  EXPECT_LE(worst_drift, 0.03);  // measured 0.0223
  EXPECT_LT(lowest, 0.04);  // measured 0.0251 (the wall gap is half the 3 cm edge)
  // Measured 1.017: the count takes the tets inside the undeformed inner sphere moved with the
  // bowl's mean shift, which the squashed bowl lets exceed 1 (1.15 at 0.33 s); 0.78 when back-traces
  // leaving the liquid were clamped centrally and carried water through the wall.
  EXPECT_GT(inside / inside0, 0.9);
}
