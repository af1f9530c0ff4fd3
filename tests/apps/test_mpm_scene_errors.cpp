// Bad mpm scenes (the keys of the `mpm` block and the mpm probe kinds): each one exits with code 2
// from both `tetfsi validate` and `tetfsi run`, with the same message naming the key by its JSON
// pointer, and nothing crashes. The cases cover what only the geometry shows (missing, unreadable
// and open surface files, files without triangles, particles or membrane nodes outside the grid,
// empty regions, symmetry planes that miss the membrane) as well as ranges and cross-key rules.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace tetfsi::test;

namespace {

std::string run_tetfsi(const std::string& args, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

/// A small valid scene: an elastic ball above a clamped square membrane in a unit box.
json base_scene() {
  return json::parse(R"({
    "simulation": {"end_time": 1e-3, "frame_rate": 1000, "gravity": [0, 0, -9.81]},
    "mpm": {
      "grid": {"lo": [0, 0, 0], "hi": [1, 1, 1], "cell": 0.1},
      "bodies": [{"name": "ball", "shape": {"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.2},
                  "spacing": 0.05,
                  "material": {"type": "linear_elastic", "density": 1000, "youngs_modulus": 1e6, "poissons_ratio": 0.3}}],
      "membrane": {"shape": {"type": "rectangle", "origin": [0.1, 0.1, 0.2], "u": [0.8, 0, 0], "v": [0, 0.8, 0]},
                   "element_size": 0.1, "thickness": 1e-3, "density": 1000, "youngs_modulus": 1e6,
                   "poissons_ratio": 0.3, "fixed": [{"region": {"type": "boundary"}}]}
    }})");
}

json gas_body() {
  return json::parse(R"({"name": "gas", "shape": {"type": "box", "lo": [0.3, 0.3, 0.5], "hi": [0.5, 0.5, 0.7]},
                         "spacing": 0.05, "material": {"type": "ideal_gas", "density": 1.2}, "pressure": 1e5})");
}

struct Case {
  std::string name;
  std::function<void(json&)> edit;
  std::string pointer, fragment;
};

}  // namespace

TEST(MpmSceneErrors, ValidateAndRunRejectEachWithExit2AndThePointer) {
  TempDir dir("mpm_errors");
  const fs::path d = dir.path();
  std::ofstream(d / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";  // one triangle: not closed
  std::ofstream(d / "lines.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n";  // no faces at all
  std::ofstream(d / "garbage.stl") << "this is not a mesh\n\x01\x02\x03";
  // Two triangles sharing the edge 1-2 in the same direction: inconsistent orientation.
  std::ofstream(d / "flipped.obj") << "v 0.2 0.2 0.3\nv 0.6 0.2 0.3\nv 0.2 0.6 0.3\nv 0.6 0.6 0.3\nf 1 2 3\nf 1 2 4\n";
  const std::string file_of = (d / "open.obj").string();
  auto file_shape = [](const fs::path& f) { return json{{"type", "file"}, {"file", f.string()}}; };
  const std::vector<Case> cases = {
      {"body_file_missing", [&](json& s) { s["mpm"]["bodies"][0]["shape"] = file_shape(d / "nope.obj"); },
       "/mpm/bodies/0/shape/file", "file not found"},
      {"body_file_open", [&](json& s) { s["mpm"]["bodies"][0]["shape"] = file_shape(d / "open.obj"); },
       "/mpm/bodies/0/shape/file", "a particle body needs a closed surface"},
      {"body_file_lines_only", [&](json& s) { s["mpm"]["bodies"][0]["shape"] = file_shape(d / "lines.obj"); },
       "/mpm/bodies/0/shape/file", "lines.obj"},
      {"body_file_garbage", [&](json& s) { s["mpm"]["bodies"][0]["shape"] = file_shape(d / "garbage.stl"); },
       "/mpm/bodies/0/shape/file", "garbage.stl"},
      {"membrane_file_missing", [&](json& s) { s["mpm"]["membrane"]["shape"] = file_shape(d / "nope.ply"); },
       "/mpm/membrane/shape/file", "file not found"},
      {"membrane_file_lines_only", [&](json& s) { s["mpm"]["membrane"]["shape"] = file_shape(d / "lines.obj"); },
       "/mpm/membrane/shape/file", "lines.obj"},
      {"membrane_file_garbage", [&](json& s) { s["mpm"]["membrane"]["shape"] = file_shape(d / "garbage.stl"); },
       "/mpm/membrane/shape/file", "garbage.stl"},
      {"membrane_file_misoriented", [&](json& s) {
         s["mpm"]["membrane"]["shape"] = file_shape(d / "flipped.obj");
         s["mpm"]["membrane"]["fixed"] = json::array(); },
       "/mpm/membrane/shape", "opposite orientation"},
      {"volume_of_open_membrane", [&](json& s) {
         s["probes"] = {{{"name", "v"}, {"kind", "membrane_volume"}}}; },
       "/probes/0/kind", "needs a closed membrane"},
      {"volume_of_open_file_membrane", [&](json& s) {
         s["mpm"]["membrane"]["shape"] = {{"type", "file"}, {"file", file_of}, {"translation", {0.1, 0.1, 0.1}},
                                          {"unit_scale", 0.5}};
         s["probes"] = {{{"name", "v"}, {"kind", "membrane_volume"}}}; },
       "/probes/0/kind", "needs a closed membrane"},
      {"particles_outside_grid", [](json& s) { s["mpm"]["bodies"][0]["shape"]["center"] = {0.9, 0.5, 0.5}; },
       "/mpm/bodies/0/shape", "outside the grid"},
      {"lattice_on_node_planes", [](json& s) { s["mpm"]["bodies"][0]["shape"]["radius"] = 0.175; },
       "/mpm/bodies/0/shape", "lies on a grid node plane"},
      {"membrane_outside_grid", [](json& s) { s["mpm"]["membrane"]["shape"]["origin"] = {0.5, 0.5, 0.2}; },
       "/mpm/membrane/shape", "outside the grid"},
      {"empty_fixed_box", [](json& s) {
         s["mpm"]["membrane"]["fixed"] = {{{"region", {{"type", "box"}, {"lo", {0.4, 0.4, 0.5}}, {"hi", {0.6, 0.6, 0.6}}}}}}; },
       "/mpm/membrane/fixed/0/region", "selects no membrane node"},
      {"empty_fixed_plane", [](json& s) {
         s["mpm"]["membrane"]["fixed"] = {{{"region", {{"type", "plane"}, {"axis", "x"}, {"position", 0.55}}}}}; },
       "/mpm/membrane/fixed/0/region", "selects no membrane node"},
      {"boundary_of_closed_membrane", [](json& s) {
         s["mpm"]["membrane"]["shape"] = {{"type", "sphere"}, {"center", {0.5, 0.5, 0.5}}, {"radius", 0.3}}; },
       "/mpm/membrane/fixed/0/region", "no free edge"},
      {"symmetry_plane_inside_grid", [](json& s) {
         s["mpm"]["symmetry_planes"] = {{{"axis", "x"}, {"position", 0.5}}}; },
       "/mpm/symmetry_planes/0/position", "the grid's lower face"},
      {"symmetry_plane_cuts_membrane_away", [](json& s) {
         s["mpm"]["membrane"]["shape"]["origin"] = {0.1, 0.1, 0.05};
         s["mpm"]["membrane"]["shape"]["u"] = {0.8, 0, 0};
         s["mpm"]["membrane"]["shape"]["v"] = {0, 0, -0.04};
         s["mpm"]["grid"]["lo"] = {0, 0, 0.02};
         s["mpm"]["symmetry_planes"] = {{{"axis", "z"}, {"position", 0.02}}}; },
       "/mpm/symmetry_planes", "no element"},
      {"spacing_above_cell", [](json& s) { s["mpm"]["bodies"][0]["spacing"] = 0.2; },
       "/mpm/bodies/0/spacing", "between cell / 6 and the cell"},
      {"huge_grid", [](json& s) { s["mpm"]["grid"]["cell"] = 1e-4; }, "/mpm/grid/cell", "nodes (at most"},
      {"huge_membrane", [](json& s) { s["mpm"]["membrane"]["element_size"] = 1e-5; },
       "/mpm/membrane/element_size", "elements (at most"},
      {"source_unknown_body", [](json& s) {
         s["mpm"]["sources"] = {{{"body", "air"}, {"region", {{"lo", {0.4, 0.4, 0.4}}, {"hi", {0.5, 0.5, 0.5}}}},
                                 {"mass_rate", 1.0}, {"end_time", 1e-3}}}; },
       "/mpm/sources/0/body", "no body named \"air\""},
      {"source_of_solid_body", [](json& s) {
         s["mpm"]["sources"] = {{{"body", "ball"}, {"region", {{"lo", {0.4, 0.4, 0.4}}, {"hi", {0.5, 0.5, 0.5}}}},
                                 {"mass_rate", 1.0}, {"end_time", 1e-3}}}; },
       "/mpm/sources/0/body", "is a solid"},
      {"source_ends_before_start", [](json& s) {
         s["mpm"]["bodies"].push_back(gas_body());
         s["mpm"]["sources"] = {{{"body", "gas"}, {"region", {{"lo", {0.4, 0.4, 0.6}}, {"hi", {0.5, 0.5, 0.7}}}},
                                 {"mass_rate", 1.0}, {"start_time", 2e-3}, {"end_time", 1e-3}}}; },
       "/mpm/sources/0/end_time", "end_time > start_time"},
      {"source_outside_grid", [](json& s) {
         s["mpm"]["bodies"].push_back(gas_body());
         s["mpm"]["sources"] = {{{"body", "gas"}, {"region", {{"lo", {0.9, 0.9, 0.9}}, {"hi", {1.2, 1.2, 1.2}}}},
                                 {"mass_rate", 1.0}, {"end_time", 1e-3}}}; },
       "/mpm/sources/0/region", "outside the grid"},
      {"source_runaway_mass_rate", [](json& s) {
         s["mpm"]["bodies"].push_back(gas_body());
         s["mpm"]["sources"] = {{{"body", "gas"}, {"region", {{"lo", {0.4, 0.4, 0.6}}, {"hi", {0.5, 0.5, 0.7}}}},
                                 {"mass_rate", 1e9}, {"end_time", 1.0}}}; },
       "/mpm/sources/0/mass_rate", "particles (at most"},
      {"pressure_on_solid", [](json& s) { s["mpm"]["bodies"][0]["pressure"] = 1e5; },
       "/mpm/bodies/0/pressure", "linear_elastic body starts unstressed"},
      {"pressure_and_energy", [](json& s) {
         json g = gas_body();
         g["internal_energy"] = 2.5e5;
         s["mpm"]["bodies"].push_back(g); },
       "/mpm/bodies/1/internal_energy", "either pressure or internal_energy"},
      {"water_in_tension_with_pressure", [](json& s) {
         json w = gas_body();
         w["material"] = {{"type", "mie_gruneisen"}, {"density", 1000}, {"c0", 1647}, {"s", 1.921}, {"gamma0", 0.1}};
         w["density"] = 990;
         s["mpm"]["bodies"].push_back(w); },
       "/mpm/bodies/1/pressure", "whatever the energy"},
      {"duplicate_body_name", [](json& s) {
         json g = gas_body();
         g["name"] = "ball";
         s["mpm"]["bodies"].push_back(g); },
       "/mpm/bodies/1/name", "duplicate body name"},
      {"membrane_named_as_body", [](json& s) { s["mpm"]["membrane"]["name"] = "ball"; },
       "/mpm/membrane/name", "also the name of a body"},
      {"particle_probe_unknown_body", [](json& s) {
         s["probes"] = {{{"name", "z"}, {"kind", "particle_point"}, {"body", "bal"}, {"point", {0.5, 0.5, 0.7}},
                         {"quantity", "z"}}}; },
       "/probes/0/body", "no body named \"bal\""},
      {"energy_probe_unknown_body", [](json& s) {
         s["probes"] = {{{"name", "e"}, {"kind", "body_energy"}, {"body", "sheet"}}}; },
       "/probes/0/body", "not the membrane's name"},
      {"old_example_key", [](json& s) { s["mpm"]["example"] = "gas_expansion"; }, "/mpm/example", "unknown key"},
      {"missing_membrane", [](json& s) { s["mpm"].erase("membrane"); }, "/mpm/membrane", "missing required key"},
      {"unknown_body_shape", [](json& s) { s["mpm"]["bodies"][0]["shape"]["type"] = "torus"; },
       "/mpm/bodies/0/shape/type", "got \"torus\""},
      {"unknown_membrane_shape", [](json& s) { s["mpm"]["membrane"]["shape"]["type"] = "spere"; },
       "/mpm/membrane/shape/type", "did you mean \"sphere\"?"},
      {"parallel_rectangle_edges", [](json& s) { s["mpm"]["membrane"]["shape"]["v"] = {0.4, 0, 0}; },
       "/mpm/membrane/shape/v", "parallel"},
      {"zero_cylinder_axis", [](json& s) {
         s["mpm"]["membrane"]["shape"] = {{"type", "cylinder"}, {"base", {0.5, 0.5, 0.2}}, {"axis", {0, 0, 0}}, {"radius", 0.3}}; },
       "/mpm/membrane/shape/axis", "non-zero"},
      {"incompressible_solid", [](json& s) { s["mpm"]["bodies"][0]["material"]["poissons_ratio"] = 0.5; },
       "/mpm/bodies/0/material/poissons_ratio", "got 0.5"},
      {"bad_components", [](json& s) { s["mpm"]["membrane"]["fixed"][0]["components"] = "w"; },
       "/mpm/membrane/fixed/0/components", "got \"w\""},
      {"grid_hi_below_lo", [](json& s) { s["mpm"]["grid"]["hi"] = {1, -1, 1}; }, "/mpm/grid/hi", "expected hi > lo"},
      {"no_bodies", [](json& s) { s["mpm"]["bodies"] = json::array(); }, "/mpm/bodies", "at least 1"},
      {"with_tet_fluid", [](json& s) {
         s["domain"] = {{"lo", {0, 0, 0}}, {"hi", {1, 1, 1}}};
         s["fluid"] = {{"type", "smoke"}}; },
       "/fluid/type", "mpm scene"},
      {"mpm_probe_without_mpm", [](json& s) {
         s.erase("mpm");
         s["solids"] = {{{"name", "b"}, {"geometry", {{"type", "sphere"}, {"radius", 0.1}}},
                         {"material", {{"density", 1000}, {"youngs_modulus", 1e5}, {"poissons_ratio", 0.3}}}}};
         s["probes"] = {{{"name", "r"}, {"kind", "membrane_volume"}}}; },
       "/probes/0/kind", "needs an /mpm block"},
  };
  // The base scene itself is valid.
  {
    std::ofstream(d / "base.json") << base_scene().dump(2);
    int status = -1;
    const auto msg = run_tetfsi("validate " + (d / "base.json").string(), &status);
    ASSERT_EQ(status, 0) << msg;
  }
  for (const auto& c : cases) {
    json s = base_scene();
    c.edit(s);
    const fs::path file = d / (c.name + ".json");
    std::ofstream(file) << s.dump(2);
    std::string messages[2];
    int k = 0;
    for (const std::string& cmd : std::vector<std::string>{"validate ", "run -q --out " + (d / "out").string() + " "}) {
      int status = -1;
      const std::string msg = run_tetfsi(cmd + file.string(), &status);
      EXPECT_EQ(status, 2) << c.name << ": " << cmd << msg;
      EXPECT_NE(msg.find(file.filename().string() + ": " + c.pointer + ": "), std::string::npos) << c.name << ": " << msg;
      EXPECT_NE(msg.find(c.fragment), std::string::npos) << c.name << ": " << msg;
      messages[k++] = msg.substr(msg.find(file.filename().string() + ": "));
    }
    // The same verdict and the same first message line.
    EXPECT_EQ(messages[0].substr(0, messages[0].find('\n')), messages[1].substr(0, messages[1].find('\n'))) << c.name;
  }
  EXPECT_GE(cases.size(), 40u);
}
