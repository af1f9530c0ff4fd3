// Inputs that ended in an internal error, an unclear failure or a silently ignored value
// (issue 44): bad output paths, a solid inside an obstacle, an impossible Young's modulus, an
// unknown command, values the run ignores or cuts, a fixed region that misses its solid. Each is
// refused with exit 2 naming the key or path, or warned about by `validate` and `run` alike.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using tetfsi::test::TempDir;

namespace {

/// A soft box above a floor plane (solid runner), coarse.
json box_on_floor() {
  return json::parse(R"({
    "simulation": {"end_time": 0.02, "dt": 0.01, "frame_rate": 100},
    "solids": [{"name": "box", "geometry": {"type": "box", "size": [0.3, 0.3, 0.3]},
                "placement": {"translation": [0, 0.5, 0]},
                "material": {"density": 1000, "youngs_modulus": 1e5, "poissons_ratio": 0.3}}],
    "obstacles": {"planes": [{"point": [0, 0, 0], "normal": [0, 1, 0]}]}
  })");
}

/// A ball in a closed box of water (coupled runner), coarse.
json ball_in_water() {
  return json::parse(R"({
    "simulation": {"end_time": 0.005, "dt": 0.005, "frame_rate": 100},
    "domain": {"lo": [-0.4, -0.4, -0.4], "hi": [0.4, 0.4, 0.4]},
    "mesh": {"edge_length": 0.2, "edge_length_near_solids": 0.08, "grading_distance": 0.2},
    "fluid": {"type": "liquid"},
    "solids": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.15, "subdivisions": 2},
                "material": {"density": 500, "youngs_modulus": 1e6, "poissons_ratio": 0.3}}]
  })");
}

std::string write(const fs::path& dir, const std::string& name, const json& s) {
  const fs::path p = dir / (name + ".json");
  std::ofstream(p) << s.dump(1);
  return p.string();
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool has(const std::string& text, const std::string& fragment) { return text.find(fragment) != std::string::npos; }

/// `tetfsi validate` and `tetfsi run` (into dir/out) both exit 2 naming `fragment`, without an
/// internal error.
void expect_refused(const fs::path& dir, const std::string& scene, const std::string& fragment) {
  SCOPED_TRACE(scene);
  int v = -1, r = -1;
  const std::string vout = tetfsi::test::tetfsi_cmd("validate " + scene, &v);
  const std::string rout = tetfsi::test::tetfsi_cmd("run " + scene + " --out " + (dir / "out").string() + " --quiet", &r);
  EXPECT_EQ(v, 2) << vout;
  EXPECT_EQ(r, 2) << rout;
  EXPECT_TRUE(has(vout, fragment)) << vout;
  EXPECT_TRUE(has(rout, fragment)) << rout;
  EXPECT_FALSE(has(rout, "internal error")) << rout;
}

/// `tetfsi validate` accepts the scene; returns its output.
std::string expect_valid(const fs::path& dir, const std::string& name, const json& scene) {
  int status = -1;
  const std::string text = tetfsi::test::tetfsi_cmd("validate " + write(dir, name, scene), &status);
  EXPECT_EQ(status, 0) << text;
  return text;
}

}  // namespace

// Output paths taken by the wrong kind of entry ended in "internal error: filesystem error" after
// meshing and running; now exit 2 naming the path, before anything is meshed (no run.log).
TEST(UnclearInputs, BadOutputPathsAreRefusedBeforeAnyWork) {
  TempDir dir("bad_out");
  const std::string scene = write(dir.path(), "box", box_on_floor());
  struct Case {
    std::string name;
    std::function<void(const fs::path&)> prepare;  ///< given the output folder
    std::string fragment;
  };
  const std::vector<Case> cases = {
      {"object_folder_is_a_file", [](const fs::path& o) { fs::create_directories(o), std::ofstream(o / "box"); },
       "/box is a file, where the run writes a folder of frames"},
      {"pvd_is_a_folder", [](const fs::path& o) { fs::create_directories(o / "box.pvd"); },
       "/box.pvd is a folder, where the run writes a file"},
      {"frame_is_a_folder", [](const fs::path& o) { fs::create_directories(o / "surfaces" / "box_00000.ply"); },
       "box_00000.ply is a folder, where the run writes frame files"},
      {"out_is_a_file", [](const fs::path& o) { std::ofstream{o}; }, "is a file, not a folder"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path out = dir.path() / c.name;
    c.prepare(out);
    int status = -1;
    const std::string text = tetfsi::test::tetfsi_cmd("run " + scene + " --out " + out.string() + " --quiet", &status);
    EXPECT_EQ(status, 2) << text;
    EXPECT_TRUE(has(text, "error: --out " + out.string())) << text;
    EXPECT_TRUE(has(text, c.fragment)) << text;
    EXPECT_FALSE(has(text, "internal error")) << text;
    EXPECT_FALSE(fs::exists(out / "run.log")) << "the run started before the check";
  }
  int status = -1;
  std::string text = tetfsi::test::tetfsi_cmd("run " + scene + " --out /proc/tetfsi_out --quiet", &status);
  EXPECT_EQ(status, 2) << text;
  EXPECT_TRUE(has(text, "--out /proc/tetfsi_out: cannot create the folder in /proc")) << text;

  // `tetfsi mesh SURFACE OUT`: OUT a folder, or in a folder where no file can be created.
  const std::string surface = std::string(TETFSI_SOURCE_DIR) + "/data/scenes/meshes/beam.obj";
  fs::create_directories(dir.path() / "existing_dir");
  for (const auto& [target, fragment] : std::vector<std::pair<std::string, std::string>>{
           {(dir.path() / "existing_dir").string(), ": is a folder; give the name of a file to write"},
           {"/proc/x.vtu", "output /proc/x.vtu: cannot create a file there"}}) {
    text = tetfsi::test::tetfsi_cmd("mesh " + surface + " " + target + " --edge-length 0.05", &status);
    EXPECT_EQ(status, 2) << text;
    EXPECT_TRUE(has(text, fragment)) << text;
    EXPECT_FALSE(has(text, "internal error")) << text;
    EXPECT_FALSE(has(text, "tets")) << "meshed before the check: " << text;
  }
}

TEST(UnclearInputs, UnknownCommandIsNamed) {
  int status = -1;
  const std::string text = tetfsi::test::tetfsi_cmd("frobnicate", &status);
  EXPECT_EQ(status, 2) << text;
  EXPECT_TRUE(has(text, "unknown command 'frobnicate'")) << text;
  EXPECT_TRUE(has(text, "run, validate, mesh, schema and report")) << text;
}

// A solid below the floor plane stopped with "tet 0 is inverted or degenerate" after meshing.
TEST(UnclearInputs, SolidStartingInsideAnObstacleIsRefusedBeforeRunning) {
  TempDir dir("in_obstacle");
  json below = box_on_floor();
  below["solids"][0]["placement"]["translation"] = {0, -0.5, 0};
  expect_refused(dir.path(), write(dir.path(), "below", below),
                 "below.json: /solids/0/placement: solid 'box' starts inside the obstacle /obstacles/planes/0: 8 of "
                 "its 8 surface vertices lie in it, the deepest 0.65 m");
  json in_box = box_on_floor();
  in_box["obstacles"]["boxes"] = {{{"lo", {0.1, 0.6, 0.1}}, {"hi", {1, 1, 1}}}};
  expect_refused(dir.path(), write(dir.path(), "in_box", in_box),
                 "in_box.json: /solids/0/placement: solid 'box' starts inside the obstacle /obstacles/boxes/0: 1 of its "
                 "8 surface vertices");
  // Resting on the floor (its lowest face on the plane) is a valid start.
  json resting = box_on_floor();
  resting["solids"][0]["placement"]["translation"] = {0, 0.15, 0};
  expect_valid(dir.path(), "resting", resting);
}

// E = 1e300 Pa printed four raw CHOLMOD warnings and named no key. The bound is ten times
// diamond's 1.05e12 Pa (apps/scene/blocks/blocks.hpp).
TEST(UnclearInputs, YoungsModulusAboveTenTimesDiamondsIsRefused) {
  TempDir dir("stiff");
  for (const double E : {1e300, 2e13}) {
    json s = box_on_floor();
    s["solids"][0]["material"]["youngs_modulus"] = E;
    expect_refused(dir.path(), write(dir.path(), "stiff", s),
                   "stiff.json: /solids/0/material/youngs_modulus: expected a number > 0 and <= 1e+13 [Pa]");
  }
  json s = box_on_floor();
  s["solids"][0]["material"]["youngs_modulus"] = 1.05e12;  // diamond
  expect_valid(dir.path(), "diamond", s);
}

// A fixed_regions box that misses the solid passed validate and stopped the solid runner (exit 2);
// the coupled runner fixed nothing without a word. Outside the bounding box, or inside it but
// outside the solid (a corner of a ball's box): validate and run refuse it alike.
TEST(UnclearInputs, FixedRegionMissingTheSolidIsRefusedByValidateAsByRun) {
  TempDir dir("fixed_miss");
  json s = box_on_floor();
  s["solids"][0]["fixed_regions"] = {{{"lo", {5, 5, 5}}, {"hi", {6, 6, 6}}}};
  expect_refused(dir.path(), write(dir.path(), "fixed", s),
                 "fixed.json: /solids/0/fixed_regions/0: the box [5, 5, 5] to [6, 6, 6] m misses solid 'box'");
  json ball = ball_in_water();  // radius 0.15: the corner (0.12..0.15)^3 is 0.21 m or more from its centre
  ball["solids"][0]["fixed_regions"] = {{{"lo", {0.12, 0.12, 0.12}}, {"hi", {0.15, 0.15, 0.15}}}};
  expect_refused(dir.path(), write(dir.path(), "corner", ball),
                 "corner.json: /solids/0/fixed_regions/0: the box [0.12, 0.12, 0.12] to [0.15, 0.15, 0.15] m misses "
                 "solid 'ball'");
  ball["solids"][0]["fixed_regions"] = {{{"lo", {-0.02, -0.02, -0.02}}, {"hi", {0.02, 0.02, 0.02}}}};  // inside
  expect_valid(dir.path(), "centre", ball);
}

// Values the run ignored or cut without a word: a warning from validate, on run's console and in
// run.log; an emitter that would never be on is refused.
TEST(UnclearInputs, IgnoredValuesAreWarnedByValidateAndRunAlike) {
  TempDir dir("ignored");
  json solid = box_on_floor();
  solid["simulation"]["cfl"] = 0.3;
  solid["simulation"]["dt"] = 1.0 / 30;  // frame interval 0.01 s
  solid["mesh"] = {{"edge_length", 1e300}};
  json liquid = ball_in_water();
  liquid["fluid"]["regions"] = {{{"type", "below"}, {"height", 0}}};  // fill "domain" (default)
  liquid["simulation"]["cfl"] = 0.3;  // with dt
  json still = ball_in_water();  // a ball held still in smoke: the fluid runner
  still["fluid"] = {{"type", "smoke"}};
  still["solids"][0]["motion"] = {{"type", "translation"}, {"velocity", {0, 0, 0}}};
  still["obstacles"] = {{"planes", {{{"point", {0, -0.4, 0}}, {"normal", {0, 1, 0}}}}}};
  const std::vector<std::pair<json, std::vector<std::string>>> cases = {
      {solid,
       {"warning: /simulation/cfl: ignored: the solid runner (which runs this scene) has no CFL step",
        "warning: /simulation/dt: 0.0333333 s is longer than the frame interval 1 / frame_rate = 0.01 s",
        "warning: /mesh/edge_length: 1e+300 m is longer than every solid meshed at it"}},
      {liquid,
       {"warning: /fluid/regions: ignored: /fluid/fill is \"domain\"",
        "warning: /simulation/cfl: ignored: /simulation/dt is given"}},
      {still, {"warning: /obstacles: ignored: they are for solid contact, and the fluid runner"}},
  };
  for (const auto& [scene_json, warnings] : cases) {
    const std::string scene = write(dir.path(), "scene", scene_json);
    int v = -1, r = -1;
    const std::string vout = tetfsi::test::tetfsi_cmd("validate " + scene, &v);
    const std::string rout = tetfsi::test::tetfsi_cmd(
        "run " + scene + " --out " + (dir.path() / "out").string() + " --quiet --threads 1", &r);
    EXPECT_EQ(v, 0) << vout;
    EXPECT_EQ(r, 0) << rout;
    const std::string log = read(dir.path() / "out" / "run.log");
    for (const auto& w : warnings) {
      EXPECT_TRUE(has(vout, w)) << w << "\n" << vout;
      EXPECT_TRUE(has(rout, w)) << w << "\n" << rout;
      EXPECT_TRUE(has(log, "[warning] " + w.substr(9))) << w;
    }
  }
  // Without those keys: no warning.
  const std::string quiet = expect_valid(dir.path(), "plain", box_on_floor());
  EXPECT_FALSE(has(quiet, "warning")) << quiet;

  json smoke = ball_in_water();
  smoke["fluid"] = {{"type", "smoke"}};
  smoke["emitters"] = {{{"shape", {{"type", "box"}, {"lo", {-0.1, -0.4, -0.1}}, {"hi", {0.1, -0.3, 0.1}}}},
                        {"start_time", 0.5}, {"end_time", 0.2}}};
  expect_refused(dir.path(), write(dir.path(), "emitter", smoke),
                 "emitter.json: /emitters/0/end_time: expected end_time > start_time (0.5 s)");
}
