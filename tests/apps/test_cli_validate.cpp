// `tetfsi validate` / `tetfsi run` on malformed scenes: each must exit with code 2 and name the
// offending key by its JSON pointer, with what was expected. Committed scenes must validate.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json base_scene() {
  return json::parse(R"({
    "simulation": {"end_time": 1.0, "dt": 0.01},
    "domain": {"lo": [-1, -1, -1], "hi": [1, 1, 1]},
    "fluid": {"type": "smoke"},
    "solids": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.2},
                "material": {"density": 1000, "youngs_modulus": 1e5, "poissons_ratio": 0.3}}],
    "probes": [{"name": "v", "kind": "solid_volume", "solid": "ball"}]
  })");
}

struct Case {
  std::string name;
  std::function<void(json&)> edit;
  std::string pointer;   // must appear in the message as "<file>: <pointer>: "
  std::string fragment;  // must appear in the message too
};

std::string write(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / (name + ".json");
  std::ofstream(p) << text;
  return p.string();
}

std::string run_tetfsi(const std::string& args, int* status) {
  return tetfsi::test::run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

/// Each case edits `base` and must fail validation with exit code 2, naming its pointer and fragment.
void expect_named_errors(const json& base, const std::vector<Case>& cases) {
  tetfsi::test::TempDir dir("validate");
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    json s = base;
    c.edit(s);
    const std::string file = write(dir.path(), c.name, s.dump(2));
    int status = -1;
    const std::string out = run_tetfsi("validate " + file, &status);
    EXPECT_EQ(status, 2) << out;
    EXPECT_NE(out.find(c.name + ".json: " + c.pointer + ": "), std::string::npos) << out;
    EXPECT_NE(out.find(c.fragment), std::string::npos) << out;
  }
}

}  // namespace

TEST(CliValidate, MalformedScenesNameTheKeyAndExitWith2) {
  const std::vector<Case> cases = {
      {"negative_E", [](json& s) { s["solids"][0]["material"]["youngs_modulus"] = -5; },
       "/solids/0/material/youngs_modulus", "expected a number > 0 and <= 1e+13 [Pa], got -5"},
      {"nu_half", [](json& s) { s["solids"][0]["material"]["poissons_ratio"] = 0.5; },
       "/solids/0/material/poissons_ratio", "< 0.5"},
      {"nu_minus_one", [](json& s) { s["solids"][0]["material"]["poissons_ratio"] = -1; },
       "/solids/0/material/poissons_ratio", "> -1"},
      {"zero_density", [](json& s) { s["solids"][0]["material"]["density"] = 0; },
       "/solids/0/material/density", "got 0"},
      {"zero_dt", [](json& s) { s["simulation"]["dt"] = 0; }, "/simulation/dt", "expected a number > 0"},
      {"negative_end", [](json& s) { s["simulation"]["end_time"] = -1; }, "/simulation/end_time", "got -1"},
      {"typo_key", [](json& s) { s["simulation"]["frame_rat"] = 30; }, "/simulation/frame_rat",
       "did you mean \"frame_rate\"?"},
      {"typo_enum", [](json& s) { s["fluid"]["type"] = "smok"; }, "/fluid/type", "did you mean \"smoke\"?"},
      {"short_vector", [](json& s) { s["domain"]["lo"] = {0, 0}; }, "/domain/lo", "an array of 3 numbers"},
      {"inverted_box", [](json& s) { s["domain"]["hi"] = {1, -2, 1}; }, "/domain/hi", "hi > lo"},
      {"missing_file",
       [](json& s) { s["solids"][0]["geometry"] = {{"type", "mesh"}, {"file", "no_such_model.obj"}}; },
       "/solids/0/geometry/file", "file not found"},
      {"wrong_type", [](json& s) { s["solids"][0]["geometry"]["radius"] = "big"; },
       "/solids/0/geometry/radius", "got \"big\""},
      {"missing_block", [](json& s) { s.erase("simulation"); }, "/simulation", "missing required key"},
      {"duplicate_name", [](json& s) { s["solids"].push_back(s["solids"][0]); }, "/solids/1/name",
       "duplicate solid name"},
      {"unknown_probe_solid", [](json& s) { s["probes"][0]["solid"] = "bal"; }, "/probes/0/solid",
       "no solid named \"bal\""},
      {"zero_axis",
       [](json& s) {
         s["solids"][0]["motion"] = {{"type", "rotation"}, {"axis", {0, 0, 0}}, {"angular_velocity", 1}};
       },
       "/solids/0/motion/axis", "non-zero"},
      {"bad_surfaces", [](json& s) { s["export"]["surfaces"] = "vtk"; }, "/export/surfaces",
       "one of \"none\", \"ply\", \"obj\""},
      {"string_number", [](json& s) { s["mesh"]["edge_length"] = "0.1"; }, "/mesh/edge_length",
       "got \"0.1\""},
      {"key_of_other_variant", [](json& s) { s["solids"][0]["geometry"]["thickness"] = 0.1; },
       "/solids/0/geometry/thickness", "belongs to type \"bowl\", \"sheet\" or \"sphere_shell\""},
      {"fluid_without_domain", [](json& s) { s.erase("domain"); }, "/domain", "needs a domain"},
      {"fractional_threads", [](json& s) { s["simulation"]["threads"] = 1.5; }, "/simulation/threads",
       "an integer"},
      {"no_material", [](json& s) { s["solids"][0].erase("material"); }, "/solids/0/material",
       "missing required key: expected an object"},
      {"empty_scene", [](json& s) { s = {{"simulation", {{"end_time", 1}}}}; }, "/solids", "nothing to simulate"},
      {"not_an_array", [](json& s) { s["solids"] = {{"name", "x"}}; }, "/solids", "an array"},
      {"spring_zero_stiffness",
       [](json& s) { s["solids"][0]["springs"] = json::parse(R"([{"point": [0, 0, 0], "stiffness": 0}])"); },
       "/solids/0/springs/0/stiffness", "expected a number > 0 [N/m], got 0"},
      {"spring_region_and_point",
       [](json& s) {
         s["solids"][0]["springs"] = json::parse(
             R"([{"region": {"lo": [-1, -1, -1], "hi": [1, 1, 1]}, "point": [0, 0, 0], "stiffness": 10}])");
       },
       "/solids/0/springs/0", "expected either `region` or `point`, got both"},
  };
  ASSERT_GE(cases.size(), 15u);
  expect_named_errors(base_scene(), cases);
}

TEST(CliValidate, BadShellScenesAreNamed) {
  // A liquid-filled sphere_shell alone (fluid.fill = cavities), as data/scenes/filled_toy*.json.
  const json toy = json::parse(R"({
    "simulation": {"end_time": 0.1, "dt": 0.01},
    "fluid": {"type": "liquid", "fill": "cavities"},
    "solids": [{"name": "toy", "geometry": {"type": "sphere_shell", "radius": 0.3, "thickness": 0.05},
                "material": {"density": 1000, "youngs_modulus": 1e5, "poissons_ratio": 0.3}}],
    "coupling": {"scheme": "simultaneous"}
  })");
  const std::vector<Case> cases = {
      {"wall_too_thick", [](json& s) { s["solids"][0]["geometry"]["thickness"] = 0.3; },
       "/solids/0/geometry/thickness", "expected a wall thickness < radius"},
      {"cavity_fill_with_domain", [](json& s) { s["domain"] = {{"lo", {-1, -1, -1}}, {"hi", {1, 1, 1}}}; },
       "/domain", "remove the domain box"},
      {"shell_without_fluid", [](json& s) { s["fluid"] = {{"type", "none"}}; }, "/solids/0/geometry/type",
       "needs a liquid or smoke fluid"},
      {"cavity_fill_without_shell",
       [](json& s) { s["solids"][0]["geometry"] = {{"type", "sphere"}, {"radius", 0.3}}; }, "/fluid/fill",
       "expected exactly one solid, a sphere_shell"},
  };
  expect_named_errors(toy, cases);
}

TEST(CliValidate, SpringRegionWithoutNodesNamesSolidAndSpring) {
  // Valid as JSON, but the region misses the ball: found when the solid is meshed (solid runner),
  // reported as an input error (exit 2) naming the solid, the spring and its key.
  tetfsi::test::TempDir dir("validate");
  json s = base_scene();
  s.erase("fluid");
  s.erase("domain");
  s["simulation"]["end_time"] = 0.02;
  s["solids"][0]["springs"] = json::parse(
      R"([{"name": "holder", "region": {"lo": [0.5, 0.5, 0.5], "hi": [0.6, 0.6, 0.6]}, "stiffness": 100}])");
  int status = -1;
  const std::string out =
      run_tetfsi("run " + write(dir.path(), "empty_spring", s.dump()) + " --out " + (dir.path() / "o").string(), &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("/solids/0/springs/0/region: spring 'holder' of solid 'ball': the box holds no node"),
            std::string::npos)
      << out;
}

TEST(CliValidate, SyntaxErrorGivesLineAndColumn) {
  tetfsi::test::TempDir dir("validate");
  const std::string file = write(dir.path(), "syntax", "{\n  \"simulation\": {\n    \"end_time\": 1.0,,\n  }\n}\n");
  int status = -1;
  const std::string out = run_tetfsi("validate " + file, &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("syntax.json: JSON syntax error at line 3, column 21: while parsing object key - unexpected ','"), std::string::npos) << out;
}

TEST(CliValidate, DuplicateKeysAndNumberOverflow) {
  tetfsi::test::TempDir dir("validate");
  const std::string dup = R"({"simulation": {"end_time": 1},
    "solids": [{"name": "a", "geometry": {"type": "box", "size": [1, 1, 1]},
                "material": {"density": 1, "youngs_modulus": 1, "poissons_ratio": 0.2, "density": 2}}]})";
  int status = -1;
  std::string out = run_tetfsi("validate " + write(dir.path(), "dup", dup), &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("dup.json: /solids/0/material/density: duplicate key"), std::string::npos) << out;
  out = run_tetfsi("validate " + write(dir.path(), "big", "{\n \"simulation\": {\"end_time\": 1e400}}"), &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("big.json: JSON error at line 2, column 29: number overflow"), std::string::npos) << out;
}

TEST(CliValidate, EveryProblemIsReportedNotJustTheFirst) {
  tetfsi::test::TempDir dir("validate");
  json s = base_scene();
  s["simulation"]["dt"] = -1;
  s["solids"][0]["material"]["density"] = -2;
  s["fluid"]["viscosty"] = 0.1;
  int status = -1;
  const std::string out = run_tetfsi("validate " + write(dir.path(), "three", s.dump()), &status);
  EXPECT_EQ(status, 2);
  EXPECT_NE(out.find("/simulation/dt"), std::string::npos) << out;
  EXPECT_NE(out.find("/solids/0/material/density"), std::string::npos) << out;
  EXPECT_NE(out.find("/fluid/viscosty: unknown key \"viscosty\"; did you mean \"viscosity\"?"),
            std::string::npos) << out;
  EXPECT_NE(out.find("3 problem(s)"), std::string::npos) << out;
}

TEST(CliValidate, InvalidSceneRunsNothing) {
  tetfsi::test::TempDir dir("validate");
  json s = base_scene();
  s["solids"][0]["material"]["poissons_ratio"] = 0.7;
  const fs::path out_dir = dir.path() / "out";
  int status = -1;
  const std::string out = run_tetfsi("run " + write(dir.path(), "bad", s.dump()) + " --out " + out_dir.string(), &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_FALSE(fs::exists(out_dir)) << "an invalid scene must not create output";
}

TEST(CliValidate, CommittedScenesAreValid) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes")) {
    if (e.path().extension() != ".json") continue;
    ++count;
    int status = -1;
    const std::string out = run_tetfsi("validate " + e.path().string(), &status);
    EXPECT_EQ(status, 0) << e.path() << ": " << out;
  }
  EXPECT_GE(count, 1);
}

TEST(CliValidate, DocExamplesAreValid) {
  // docs/examples read the bunny from the shared data folder next to the repository.
  ASSERT_TRUE(fs::exists(fs::path(TETFSI_SHARED_DIR) / "data" / "bunny.obj"));
  for (const auto& e : fs::directory_iterator(fs::path(TETFSI_SOURCE_DIR) / "docs" / "examples")) {
    int status = -1;
    const std::string out = run_tetfsi("validate " + e.path().string(), &status);
    EXPECT_EQ(status, 0) << e.path() << ": " << out;
  }
}

TEST(CliValidate, HelpVersionAndBadOptions) {
  int status = -1;
  std::string out = run_tetfsi("--help", &status);
  EXPECT_EQ(status, 0);
  EXPECT_NE(out.find("run"), std::string::npos);
  out = run_tetfsi("--version", &status);
  EXPECT_EQ(status, 0);
  EXPECT_NE(out.find("tetfsi 0."), std::string::npos) << out;
  out = run_tetfsi("run", &status);  // missing scene
  EXPECT_EQ(status, 2) << out;
  out = run_tetfsi("validate /no/such/scene.json", &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("cannot read the scene file"), std::string::npos) << out;
}

TEST(CliValidate, ViscosityIsUsedAndRangeChecked) {
  // The tet fluid is viscous (fluid/viscosity/): a viscosity > 0 is accepted without a warning;
  // negative or beyond 1e9 Pa s is refused naming the key.
  tetfsi::test::TempDir dir("validate");
  for (const double mu : {0.0, 1.0, -1.0, 1e12}) {
    json s = base_scene();
    s["fluid"] = json::parse(R"({"type": "liquid", "density": 1000})");
    s["fluid"]["viscosity"] = mu;
    int status = -1;
    const std::string out = run_tetfsi("validate " + write(dir.path(), "mu", s.dump()), &status);
    const bool valid = mu >= 0 && mu <= 1e9;
    EXPECT_EQ(status, valid ? 0 : 2) << out;
    EXPECT_EQ(out.find("/fluid/viscosity") != std::string::npos, !valid) << out;
  }
}
