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
// slower (the pressure sucked the water into the wall and the wall up). Not checked here, a known
// gap (fluid/README.md): at this size (3 cells of water) the level set still loses about 2% of the
// water per step on the mesh that follows the bowl (stats.csv volume_drift, printed); the
// restoration puts it back, here into the bowl, with a pool mostly into the pool.
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
/// the inner sphere, centre moved by `shift`, and below the rim) and its mean velocity.
struct Liquid {
  double volume = 0, inside = 0;
  Eigen::Vector3d mean_velocity = Eigen::Vector3d::Zero();
};

Liquid liquid_of(const mesh::io::UnstructuredGrid& g, const Eigen::Vector3d& shift) {
  const auto& fraction = field(g.cell_data, "liquid_fraction");
  const auto& velocity = field(g.cell_data, "velocity");
  const Eigen::Vector3d centre = kBowlCentre + shift;
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
  const double inside0 = liquid_of(mesh::io::read_vtu(out / "fluid" / "fluid_00000.vtu"), Eigen::Vector3d::Zero()).inside;
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
    const Liquid l = liquid_of(mesh::io::read_vtu(out / "fluid" / fmt::format("fluid_{:05d}.vtu", k)), shift);
    std::printf("t = %.4f s: water vy %.4f, bowl vy %.4f m/s against -g t = %.4f; water in the bowl %.4f of t = 0\n",
                t, l.mean_velocity.y(), bowl_velocity.y(), -kG * t, l.inside / inside0);
    EXPECT_NEAR(l.mean_velocity.y() / (-kG * t), 1.0, 0.02) << "t = " << t;
    EXPECT_NEAR(bowl_velocity.y() / (-kG * t), 1.0, 0.02) << "t = " << t;
    EXPECT_GT(l.inside / inside0, 0.99) << "t = " << t;
  }
  // The first steps redistance and restore the initial level set (-12%, +17% here either way).
  const Csv stats = read_csv(out / "stats.csv");
  double drift = 0;
  for (std::size_t r = 3; r < stats.rows.size(); ++r) drift += stats.at(r, "volume_drift") / (stats.rows.size() - 3);
  std::printf("mean volume drift of a step from step 4 on, before the restoration: %+.4f (not checked)\n", drift);
}
