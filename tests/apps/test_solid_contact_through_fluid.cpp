// Deformable solids that meet through the fluid (coupling.solid_contact,
// solid/contact/surface_contact.hpp): data/scenes/balls_collide.json, two soft balls thrown at
// each other at 1 m/s in a closed tank of water, through `tetfsi run`. The water between them is
// squeezed out, the balls meet with a film of `contact_gap` between (contact pairs active), are
// stopped and pushed apart, and the gap opens again (no pair active at the end). On every frame no
// vertex of one ball's surface comes nearer the other's surface than the film (to the penalty's
// 1/κ), the total energy never rises above its level after the start-up, and the two balls move as mirror images
// (the scene is symmetric; the mesh is not, exactly).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "solid/contact/closest_point.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

/// Smallest distance from a vertex of a to the triangles of b [m].
std::string fmt_frame(const std::string& object, int frame) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%05d.ply", object.c_str(), frame);
  return name;
}

double nearest_approach(const PlyData& a, const PlyData& b) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& x : a.positions)
    for (const auto& t : b.triangles)
      nearest = std::min(nearest, tetfsi::solid::closest_point_on_triangle(x, b.positions[t[0]], b.positions[t[1]],
                                                                           b.positions[t[2]]).distance);
  return nearest;
}

TEST(SolidContactThroughFluid, SoftBallsMeetThroughAFilmAndPartAgain) {
  TempDir dir("balls");
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/balls_collide.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["simulation"]["end_time"] = 0.3;
  scene["export"] = {{"vtu", false}, {"surfaces", "ply"}};
  const fs::path file = dir.path() / "balls.json", out = dir.path() / "out";
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " +
                                          out.string() + " --quiet 2>&1", &status);
  ASSERT_EQ(status, 0) << log;
  const Csv stats = read_csv(out / "stats.csv"), probes = read_csv(out / "probes.csv");
  std::ifstream run_log(out / "run.log");
  const std::string text((std::istreambuf_iterator<char>(run_log)), {});
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex("surface contact: .* fluid film ([0-9.eE+-]+) m"))) << text;
  const double film = std::stod(m[1]);

  // Contact while they meet, none at the end.
  // Energy: the balls start at 1 m/s in water at rest, and the first steps' projections set the
  // water moving with them (an impulsive start, +0.17% of E in step 2); from step 5 on the total
  // may only fall (advection, remeshing, the inelastic contact and the paper's scheme dissipate).
  int most_contacts = 0;
  const std::size_t start_up = 5;
  double e0 = 0, e_max = 0, kinetic_max = 0;
  for (std::size_t r = 0; r < start_up; ++r) e0 = std::max(e0, stats.at(r, "total_energy"));
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    most_contacts = std::max(most_contacts, static_cast<int>(stats.at(r, "contacts")));
    if (r >= start_up) e_max = std::max(e_max, stats.at(r, "total_energy"));
    kinetic_max = std::max(kinetic_max, stats.at(r, "solid_kinetic") + stats.at(r, "fluid_kinetic"));
  }
  EXPECT_GT(most_contacts, 0);
  EXPECT_EQ(stats.at(stats.rows.size() - 1, "contacts"), 0);
  EXPECT_LE(e_max, e0 + 1e-6 * kinetic_max);

  // Centre distance D = 0.4 m + right_x − left_x: it falls to its least at contact, then grows.
  const std::size_t last = probes.rows.size() - 1;
  double d_min = 1e9, asymmetry = 0;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    const double left = probes.at(r, "left_centre_x"), right = probes.at(r, "right_centre_x");
    d_min = std::min(d_min, 0.4 + right - left);
    asymmetry = std::max(asymmetry, std::abs(left + right));
  }
  const double d_end = 0.4 + probes.at(last, "right_centre_x") - probes.at(last, "left_centre_x");
  std::printf("film %.4f m, most contact pairs %d, centre distance least %.4f m, at the end %.4f m, "
              "largest |left + right| displacement %.2e m, E0 %.4f J, max E %.4f J\n",
              film, most_contacts, d_min, d_end, asymmetry, e0, e_max);
  EXPECT_LT(d_min, 0.2 + 2 * film + 0.01);  // they met (radius 0.1 m each, icosphere nodes on the sphere)
  EXPECT_GT(d_end, d_min + 0.05);           // and parted (by 0.1 m at 0.3 s as measured)
  EXPECT_LT(asymmetry, 0.02 * (0.4 - d_min));

  // No surface comes nearer the other than the film, on any frame.
  double nearest = std::numeric_limits<double>::infinity();
  int frames = 0;
  for (int f = 0;; ++f) {
    const fs::path left = out / "surfaces" / fmt_frame("left", f), right = out / "surfaces" / fmt_frame("right", f);
    if (!fs::exists(left) || !fs::exists(right)) break;
    const PlyData a = read_ply(left), b = read_ply(right);
    nearest = std::min({nearest, nearest_approach(a, b), nearest_approach(b, a)});
    ++frames;
  }
  std::printf("%d frames, nearest approach of the surfaces %.4f m\n", frames, nearest);
  EXPECT_GE(frames, 15);
  EXPECT_GE(nearest, 0.99 * film);
}

}  // namespace
