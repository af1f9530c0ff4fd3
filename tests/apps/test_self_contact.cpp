// Self-contact of a deformable solid (/solids/*/self_contact, solid/contact/surface_contact.hpp),
// through `tetfsi run`, checked with CGAL's self-intersection test on each frame's PLY surface:
//  - data/scenes/bowl_pinch.json: a soft bowl whose rim is pinched shut, so that its inner surface
//    folds onto itself. With self-contact on, no triangle of its surface passes through another on
//    any frame; without it the walls pass through each other (so the scene does test the contact).
//  - docs/examples/bunny_drop.json (the Stanford bunny from the shared data folder), tipped on its
//    side and dropped on the floor: with self-contact no frame has crossing triangles, no node goes
//    below the floor and the energy never rises above its start; without it the landing frame does
//    have crossing triangles.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_mesh.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

struct Folds {
  int status = -1;
  std::string log;
  int frames = 0, frames_crossing = 0;  ///< frames, and frames with intersecting triangles
  std::size_t most_pairs = 0;           ///< most intersecting triangle pairs in one frame
};

/// Runs `scene` (the solid named `solid` with self_contact on or off) in dir/<with|without> and
/// counts the frames whose surface has crossing triangles.
Folds run_folding(const TempDir& dir, nlohmann::json scene, const std::string& solid, bool self_contact,
                  double* lowest_y = nullptr) {
  const std::string name = self_contact ? "with" : "without";
  scene["solids"][0]["self_contact"] = self_contact;
  const fs::path file = dir.path() / (name + ".json"), out = dir.path() / name;
  std::ofstream(file) << scene.dump(2);
  Folds r;
  r.log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() + " --quiet 2>&1",
                      &r.status);
  if (lowest_y) *lowest_y = std::numeric_limits<double>::infinity();
  for (int f = 0;; ++f) {
    char frame[64];
    std::snprintf(frame, sizeof frame, "%s_%05d.ply", solid.c_str(), f);
    if (!fs::exists(out / "surfaces" / frame)) break;
    const PlyData ply = read_ply(out / "surfaces" / frame);
    tetfsi::mesh::SurfaceMesh surface{ply.positions, ply.triangles};
    const auto crossing = tetfsi::mesh::find_self_intersections(surface);
    ++r.frames;
    if (crossing.count > 0) ++r.frames_crossing;
    r.most_pairs = std::max(r.most_pairs, crossing.count);
    if (lowest_y)
      for (const auto& x : ply.positions) *lowest_y = std::min(*lowest_y, x.y());
  }
  std::printf("%s %s self-contact: exit %d, %d frames, %d with crossing triangles (at most %zu pairs)\n",
              solid.c_str(), name.c_str(), r.status, r.frames, r.frames_crossing, r.most_pairs);
  return r;
}

nlohmann::json read_scene(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

Folds pinch_bowl(const TempDir& dir, bool self_contact) {
  return run_folding(dir, read_scene(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/bowl_pinch.json"), "bowl",
                     self_contact);
}

TEST(SelfContact, PinchedBowlNeverPassesThroughItself) {
  TempDir dir("bowl_self");
  const Folds without = pinch_bowl(dir, false);
  const Folds with = pinch_bowl(dir, true);
  ASSERT_EQ(with.status, 0) << with.log;
  EXPECT_GE(with.frames, 15);
  EXPECT_EQ(with.frames_crossing, 0);
  EXPECT_GT(without.frames_crossing, 0) << without.log;
}

TEST(SelfContact, SoftBunnyDroppedOnTheFloorNeverPassesThroughItself) {
  const fs::path bunny = fs::path(TETFSI_SHARED_DIR) / "data/bunny.obj";
  if (!fs::exists(bunny)) GTEST_SKIP() << "no " << bunny;
  nlohmann::json scene = read_scene(fs::path(TETFSI_SOURCE_DIR) / "docs/examples/bunny_drop.json");
  scene["solids"][0]["geometry"]["file"] = bunny.string();
  scene["simulation"]["end_time"] = 0.6;
  TempDir dir("bunny_self");
  double lowest = 0;
  const Folds with = run_folding(dir, scene, "bunny", true, &lowest);
  ASSERT_EQ(with.status, 0) << with.log;
  EXPECT_EQ(with.frames, 19);
  EXPECT_EQ(with.frames_crossing, 0);
  // The floor is y = 0; contact nodes land on it to the penalty's 1e-7 relative (1e-6 m here).
  EXPECT_GE(lowest, -1e-6);
  const Csv stats = read_csv(dir.path() / "with" / "stats.csv");
  const double start = stats.at(0, "total_energy");
  for (std::size_t r = 0; r < stats.rows.size(); ++r) EXPECT_LE(stats.at(r, "total_energy"), start + 1e-9) << r;
  const Folds without = run_folding(dir, scene, "bunny", false);
  std::printf("bunny: lowest surface point %.3g m\n", lowest);
  EXPECT_GT(without.frames_crossing, 0) << without.log;
}

}  // namespace
