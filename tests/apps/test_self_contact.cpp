// Self-contact of a deformable solid (/solids/*/self_contact, solid/contact/surface_contact.hpp),
// through `tetfsi run` on data/scenes/bowl_pinch.json: a soft bowl whose rim is pinched shut, so
// that its inner surface folds onto itself. With self-contact on, no triangle of its surface passes
// through another on any frame (CGAL's self-intersection test on each frame's PLY surface); without
// it the walls pass through each other (so the scene does test the contact).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

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

Folds pinch_bowl(const TempDir& dir, bool self_contact) {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/bowl_pinch.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  const std::string name = self_contact ? "with" : "without";
  scene["solids"][0]["self_contact"] = self_contact;
  const fs::path file = dir.path() / (name + ".json"), out = dir.path() / name;
  std::ofstream(file) << scene.dump(2);
  Folds r;
  r.log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() + " --quiet 2>&1",
                      &r.status);
  for (int f = 0;; ++f) {
    char frame[64];
    std::snprintf(frame, sizeof frame, "bowl_%05d.ply", f);
    if (!fs::exists(out / "surfaces" / frame)) break;
    const PlyData ply = read_ply(out / "surfaces" / frame);
    tetfsi::mesh::SurfaceMesh surface{ply.positions, ply.triangles};
    const auto crossing = tetfsi::mesh::find_self_intersections(surface);
    ++r.frames;
    if (crossing.count > 0) ++r.frames_crossing;
    r.most_pairs = std::max(r.most_pairs, crossing.count);
  }
  std::printf("bowl %s self-contact: exit %d, %d frames, %d with crossing triangles (at most %zu pairs)\n",
              name.c_str(), r.status, r.frames, r.frames_crossing, r.most_pairs);
  return r;
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

}  // namespace
