// Solids through the fluid to rest (coupling/README.md, "Contact and closed volumes"), as a user
// writes the scene: a ball (R = 0.1 m) released at rest in the middle of a closed tank of water,
// 0.8 m across (a box, or a sphere), for density ratios 0.1, 2 and 10 and a soft (E = 1e5 Pa) and
// a stiff (E = 1e8 Pa) rubber, with the rubber's own damping (Rayleigh β = 10 ms), h = 1/30 s,
// through `tetfsi run`. Each run must
//  - finish (exit 0);
//  - keep the ball's volume within 0.1% and the water's within 1e-4 (a closed tank of
//    incompressible water leaves the ball no volume change: coupling/closed_regions.hpp);
//  - never let the ball's surface cross the container's wall (penetration below 1% of the
//    near-solid edge, measured from the surface frames);
//  - bring a heavy ball to rest on the floor, a light one against the lid, its nearest point
//    between the wall and twice the fluid film, and its kinetic energy at the end below 1% of its
//    largest;
//  - press on the wall at rest with (ρ_s − ρ_f) V g within 1% (Archimedes with the meshed volume V,
//    the contact_force probe).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "csv.hpp"
#include "mesh/primitives.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

constexpr double kRadius = 0.1, kHalfWidth = 0.4, kWater = 1000, kG = 9.81;

struct Case {
  double ratio;        ///< ρ_s / ρ_f
  double stiffness;    ///< E [Pa]
  bool sphere;         ///< spherical tank instead of the box
};

std::string name(const Case& c) {
  char s[64];
  std::snprintf(s, sizeof s, "%s_r%g_E%g", c.sphere ? "sphere" : "box", c.ratio, c.stiffness);
  return s;
}

nlohmann::json scene(const Case& c) {
  nlohmann::json s = {
      {"simulation", {{"end_time", 1.5}, {"dt", 1.0 / 30}, {"frame_rate", 30}, {"gravity", {0, -kG, 0}}}},
      {"domain", {{"lo", {-kHalfWidth, -kHalfWidth, -kHalfWidth}}, {"hi", {kHalfWidth, kHalfWidth, kHalfWidth}}}},
      {"mesh", {{"edge_length", 0.15}, {"edge_length_near_solids", 0.054}, {"grading_distance", 0.25}}},
      {"fluid", {{"type", "liquid"}, {"density", kWater}}},
      {"solids",
       {{{"name", "ball"},
         {"geometry", {{"type", "sphere"}, {"radius", kRadius}, {"subdivisions", 3}}},
         {"material",
          {{"density", c.ratio * kWater},
           {"youngs_modulus", c.stiffness},
           {"poissons_ratio", 0.3},
           {"constitutive", "neohookean"},
           {"rayleigh_beta", 0.01}}}}}},
      {"probes",
       {{{"name", "ball_volume"}, {"kind", "solid_volume"}, {"solid", "ball"}},
        {{"name", "wall_force"}, {"kind", "contact_force"}, {"solid", "ball"}}}},
      {"export", {{"vtu", false}, {"surfaces", "ply"}}}};
  if (c.sphere) {
    s["domain"]["lo"] = {-0.41, -0.41, -0.41};
    s["domain"]["hi"] = {0.41, 0.41, 0.41};
    s["domain"]["container"] = {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", kHalfWidth}};
  }
  return s;
}

struct Run {
  int status = -1;
  std::string log;
  Csv stats, probes;
  double film = 0, edge = 0;
  std::vector<fs::path> frames;  ///< the ball's surface per frame
};

Run run(const TempDir& dir, const Case& c) {
  const fs::path file = dir.path() / (name(c) + ".json"), out = dir.path() / name(c);
  std::ofstream(file) << scene(c).dump(2);
  Run r;
  r.log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() + " --quiet 2>&1",
                      &r.status);
  if (r.status != 0) return r;
  r.stats = read_csv(out / "stats.csv");
  r.probes = read_csv(out / "probes.csv");
  std::ifstream log(out / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  std::smatch m;
  if (std::regex_search(text, m, std::regex("fluid film ([0-9.eE+-]+) m"))) r.film = std::stod(m[1]);
  r.edge = 2 * r.film;  // the film is half the near-solid edge as meshed
  for (const auto& e : fs::directory_iterator(out / "surfaces"))
    if (e.path().filename().string().rfind("ball_", 0) == 0) r.frames.push_back(e.path());
  std::sort(r.frames.begin(), r.frames.end());
  return r;
}

/// The radius of the sphere inscribed in the sphere container's icosphere (its default 3
/// subdivisions), whose faces bound the water: the nearest face plane.
double sphere_container_inradius() {
  const tetfsi::mesh::SurfaceMesh s = tetfsi::mesh::make_sphere(kHalfWidth, 3);
  double r = kHalfWidth;
  for (const auto& t : s.triangles) {
    const Eigen::Vector3d& a = s.vertices[t[0]];
    r = std::min(r, std::abs((s.vertices[t[1]] - a).cross(s.vertices[t[2]] - a).normalized().dot(a)));
  }
  return r;
}

/// Distance of x inside the container's wall [m] (negative outside): the box's faces, or the
/// sphere container's inscribed sphere.
double inside_wall(const Case& c, const Eigen::Vector3d& x, double inscribed) {
  if (c.sphere) return inscribed - x.norm();
  return kHalfWidth - x.cwiseAbs().maxCoeff();
}

void check(const Case& c, const Run& r) {
  const std::string what = name(c);
  ASSERT_EQ(r.status, 0) << what << "\n" << r.log;
  ASSERT_GT(r.film, 0) << what;
  ASSERT_FALSE(r.frames.empty()) << what;
  // Volumes.
  const double v0 = r.probes.at(0, "ball_volume");
  double ball_drift = 0, water_drift = 0;
  for (std::size_t k = 0; k < r.probes.rows.size(); ++k)
    ball_drift = std::max(ball_drift, std::abs(r.probes.at(k, "ball_volume") / v0 - 1));
  for (std::size_t k = 0; k < r.stats.rows.size(); ++k)
    water_drift = std::max(water_drift, std::abs(r.stats.at(k, "closed_volume_error")));
  // Penetration and rest position from the surface frames.
  const double inscribed = sphere_container_inradius();
  double deepest = 1e9, last_gap = 1e9;
  for (std::size_t f = 0; f < r.frames.size(); ++f) {
    double gap = 1e9;
    for (const Eigen::Vector3d& x : read_ply(r.frames[f]).positions) gap = std::min(gap, inside_wall(c, x, inscribed));
    deepest = std::min(deepest, gap);
    if (f + 1 == r.frames.size()) last_gap = gap;
  }
  double kinetic_max = 0;
  for (std::size_t k = 0; k < r.stats.rows.size(); ++k) kinetic_max = std::max(kinetic_max, r.stats.at(k, "solid_kinetic"));
  const double kinetic_end = r.stats.at(r.stats.rows.size() - 1, "solid_kinetic");
  // Where it rests and how hard it presses.
  const std::size_t last = r.probes.rows.size() - 1;
  const double v = r.probes.at(last, "ball_volume");
  const double expected = (c.ratio - 1) * kWater * v * kG;  // upward floor force (> 0) or downward lid force
  const double force = r.probes.at(last, "wall_force_y");
  std::printf("%s: ball volume drift %.2e, water %.2e, nearest approach to the wall %.4f m (film %.4f m), "
              "rest gap %.4f m, kinetic end/max %.2e, wall force %.3f N against (rho_s - rho_f) V g = %.3f N\n",
              what.c_str(), ball_drift, water_drift, deepest, r.film, last_gap, kinetic_end / kinetic_max, force,
              expected);
  EXPECT_LE(ball_drift, 1e-3) << what;
  EXPECT_LE(water_drift, 1e-4) << what;
  EXPECT_GE(deepest, -0.01 * r.edge) << what;
  EXPECT_LE(last_gap, 2 * r.film) << what;
  EXPECT_LT(kinetic_end, 0.01 * kinetic_max) << what;
  EXPECT_NEAR(force, expected, 0.01 * std::abs(expected)) << what;
}

void sweep(bool sphere) {
  TempDir dir(sphere ? "sweep_sphere" : "sweep_box");
  for (double stiffness : {1e5, 1e8})
    for (double ratio : {0.1, 2.0, 10.0}) {
      const Case c{ratio, stiffness, sphere};
      check(c, run(dir, c));
    }
}

}  // namespace

TEST(ContactSweep, BallsOfThreeDensitiesAndTwoStiffnessesRestInABoxTank) { sweep(false); }

TEST(ContactSweep, BallsOfThreeDensitiesAndTwoStiffnessesRestInASphericalTank) { sweep(true); }
