// The scene schema in-process: defaults are filled in, files resolve against the scene's folder,
// "did you mean" picks the nearest key, and docs/scene_format.md is the generated text.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "apps/scene/docs.hpp"
#include "apps/scene/input_error.hpp"
#include "apps/scene/scene.hpp"
#include "apps/scene/time_step_policy.hpp"
#include "apps/scene/validate.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::scene;

TEST(SceneSchema, DefaultsAreFilledIn) {
  const Scene s = parse_scene(R"({"simulation": {"end_time": 2},
      "solids": [{"name": "b", "geometry": {"type": "box", "size": [1, 2, 3]},
                  "material": {"density": 1, "youngs_modulus": 2, "poissons_ratio": 0.25}}]})",
                              "mem.json");
  EXPECT_EQ(s["simulation"]["cfl"].get<double>(), 0.5);
  EXPECT_EQ(s["simulation"]["frame_rate"].get<double>(), 30);
  EXPECT_EQ(s["simulation"]["gravity"], Json::parse("[0, -9.81, 0]"));
  EXPECT_FALSE(s["simulation"].contains("dt"));
  EXPECT_FALSE(s.json.contains("domain"));
  EXPECT_EQ(s["fluid"]["type"], "none");
  EXPECT_EQ(s["mesh"]["edge_length"].get<double>(), 0.1);
  const auto& solid = s["solids"][0];
  EXPECT_EQ(solid["material"]["constitutive"], "stvk");
  EXPECT_EQ(solid["model"]["type"], "tet_fem");
  EXPECT_EQ(solid["motion"]["type"], "none");
  EXPECT_EQ(solid["placement"]["rotation_deg"], Json::parse("[0, 0, 0]"));
  EXPECT_EQ(s["export"]["surfaces"], "ply");
  EXPECT_TRUE(s["probes"].empty());
}

TEST(SceneSchema, VariantDefaultsFollowTheTag) {
  const Scene s = parse_scene(R"({"simulation": {"end_time": 1}, "fluid": {"type": "liquid"},
                                  "domain": {"lo": [0,0,0], "hi": [1,1,1]}})", "mem.json");
  EXPECT_EQ(s["fluid"]["density"].get<double>(), 1000);
  EXPECT_EQ(s["fluid"]["solver"]["type"], "amg");
  EXPECT_FALSE(s["fluid"].contains("buoyancy_alpha"));
}

TEST(SceneSchema, MeshFilesResolveAgainstTheSceneFolder) {
  tetfsi::test::TempDir dir("schema");
  fs::create_directories(dir.path() / "models");
  std::ofstream(dir.path() / "models" / "m.obj") << "v 0 0 0\n";
  const std::string text = R"({"simulation": {"end_time": 1}, "solids": [{"name": "m",
      "geometry": {"type": "mesh", "file": "models/m.obj", "unit_scale": 0.01},
      "material": {"density": 1, "youngs_modulus": 2, "poissons_ratio": 0.25}}]})";
  const Scene s = parse_scene(text, dir.path() / "scene.json");
  EXPECT_EQ(fs::path(s["solids"][0]["geometry"]["file"].get<std::string>()),
            (fs::absolute(dir.path()) / "models" / "m.obj").lexically_normal());
  // The same scene read from another folder does not find the file.
  EXPECT_THROW(parse_scene(text, dir.path() / "models" / "scene.json"), SceneError);
}

TEST(SceneSchema, IssuesCarryPointers) {
  try {
    parse_scene(R"({"simulation": {"end_time": 1, "dt": -1}, "fluid": {"type": "gas"}})", "x.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    ASSERT_EQ(e.issues().size(), 2u) << e.what();
    EXPECT_EQ(e.issues()[0].pointer, "/simulation/dt");
    EXPECT_EQ(e.issues()[1].pointer, "/fluid/type");
  }
}

TEST(SceneSchema, EditDistance) {
  EXPECT_EQ(edit_distance("density", "density"), 0);
  EXPECT_EQ(edit_distance("densty", "density"), 1);
  EXPECT_EQ(edit_distance("Density", "density"), 0);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3);
  EXPECT_EQ(closest_match("youngs_modulos", {"density", "youngs_modulus", "poissons_ratio"}), "youngs_modulus");
  EXPECT_EQ(closest_match("zzz", {"density", "youngs_modulus"}), "");
}

TEST(SceneSchema, CommittedDocsMatchTheSchema) {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "docs" / "scene_format.md");
  ASSERT_TRUE(in) << "docs/scene_format.md is missing";
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), schema_markdown(scene_schema()))
      << "docs/scene_format.md is out of date: regenerate it with "
         "`./build/apps/tetfsi schema > docs/scene_format.md`";
}

namespace {

/// Calls `visit(field, row_key)` for every Enum / EnumSet in the schema, with the key of the table
/// row that documents it (an array of plain values is documented in the array's own row).
void for_each_enum(const Field& f, const std::string& row_key,
                   const std::function<void(const Field&, const std::string&)>& visit) {
  if (f.kind == Kind::Enum || f.kind == Kind::EnumSet) visit(f, row_key);
  for (const auto& m : f.members) for_each_enum(m, m.key, visit);
  for (const auto& [name, extra] : f.variants)
    for (const auto& m : extra) for_each_enum(m, m.key, visit);
  if (f.kind == Kind::Array)
    for_each_enum(*f.element, f.element->kind == Kind::Object ? std::string() : row_key, visit);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace

TEST(SceneSchema, NoKeyTableInTheDocsIsEmpty) {
  const auto lines = lines_of(schema_markdown(scene_schema()));
  int tables = 0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    if (lines[i].rfind("| key |", 0) != 0) continue;
    ++tables;
    ASSERT_LT(i + 2, lines.size());
    EXPECT_EQ(lines[i + 2].rfind("| `", 0), 0u)
        << "the key table above line " << i + 3 << " of docs/scene_format.md has no rows";
  }
  EXPECT_GT(tables, 20);
}

TEST(SceneSchema, EveryEnumValueAppearsInItsRow) {
  const auto lines = lines_of(schema_markdown(scene_schema()));
  int enums = 0;
  for_each_enum(scene_schema(), "", [&](const Field& f, const std::string& row_key) {
    ++enums;
    ASSERT_FALSE(row_key.empty()) << "an enum documented in no row";
    const std::string row_start = "| `" + row_key + "` |";
    // Some keys occur in several tables (e.g. `type`): one of their rows must list every value.
    bool found = false;
    for (const auto& line : lines) {
      if (line.rfind(row_start, 0) != 0) continue;
      found = found || std::all_of(f.choices.begin(), f.choices.end(), [&](const std::string& c) {
                return line.find("`" + c + "`") != std::string::npos;
              });
    }
    EXPECT_TRUE(found) << "no row of `" << row_key << "` lists all its values";
  });
  EXPECT_GT(enums, 20);
  // The box faces are an array of strings (their spellings checked above), not of objects.
  const std::string doc = schema_markdown(scene_schema());
  EXPECT_NE(doc.find("| `open_faces` | array of strings, each `x-` \\| `x+`"), std::string::npos);
  EXPECT_EQ(doc.find("/domain/open_faces/*"), std::string::npos);
}

namespace {

/// A resolved scene of one solid box with this /simulation block.
Json scene_with_simulation(const std::string& simulation) {
  return parse_scene(R"({"simulation": )" + simulation + R"(,
      "solids": [{"name": "b", "geometry": {"type": "box", "size": [1, 1, 1]},
                  "material": {"density": 1, "youngs_modulus": 2, "poissons_ratio": 0.25}}]})",
                     "mem.json")
      .json;
}

}  // namespace

TEST(TimeStepPolicy, ReadsTheSimulationBlockOnceWithItsDefaults) {
  const TimeStepPolicy p = read_time_step_policy(scene_with_simulation(R"({"end_time": 2, "frame_rate": 40})"));
  EXPECT_FALSE(p.dt.has_value());
  EXPECT_EQ(p.cfl, 0.5);
  EXPECT_EQ(p.frame_rate, 40);
  EXPECT_EQ(p.frame_interval(), 1.0 / 40);
  EXPECT_EQ(p.fixed_step(), 1.0 / 40);  // no dt: one frame for the runners without a CFL step
  EXPECT_EQ(p.end_time, 2);
  EXPECT_EQ(p.max_steps, 1000000);
  EXPECT_EQ(p.max_step_halvings, 6);
  const TimeStepPolicy fixed = read_time_step_policy(scene_with_simulation(R"({"end_time": 1, "dt": 0.01})"));
  ASSERT_TRUE(fixed.dt.has_value());
  EXPECT_EQ(*fixed.dt, 0.01);
  EXPECT_EQ(fixed.fixed_step(), 0.01);
}

TEST(TimeStepPolicy, ABadValueIsAnInputErrorNamingItsKey) {
  const Json good = scene_with_simulation(R"({"end_time": 1, "dt": 0.01})");
  const auto message = [&](const char* key, Json value) {
    Json j = good;
    if (value.is_null()) j["simulation"].erase(key);
    else j["simulation"][key] = value;
    try {
      read_time_step_policy(j);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("dt", -1), "/simulation/dt: expected a finite number > 0, got -1");
  EXPECT_EQ(message("dt", "fast"), "/simulation/dt: expected a number, got \"fast\"");
  EXPECT_EQ(message("end_time", nullptr), "/simulation/end_time: missing");
  EXPECT_EQ(message("frame_rate", 0), "/simulation/frame_rate: expected a finite number > 0, got 0");
  EXPECT_EQ(message("cfl", std::numeric_limits<double>::infinity()).rfind("/simulation/cfl: ", 0), 0u);
  EXPECT_EQ(message("max_steps", 0.5), "/simulation/max_steps: expected a finite integer >= 1 and <= 2147483647, got 0.5");
  EXPECT_EQ(message("max_step_halvings", 21),
            "/simulation/max_step_halvings: expected a finite integer >= 0 and <= 20, got 21");
  EXPECT_THROW(read_time_step_policy(Json::object()), InputError);
}
