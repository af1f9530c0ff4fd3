// Inputs that crashed, hung or ran away (issue 18): each ends with exit 2 and a message naming
// the key or the file, from `validate` and `run` alike, with no signal, no hang, no "internal
// error" and no file written outside the output folder.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <functional>

#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include "csv.hpp"
#include "tests/test_support.hpp"
#include "tests/volume_mesh_files.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A soft box alone (solid runner).
json solid_scene() {
  return json::parse(R"({
    "simulation": {"end_time": 0.02, "dt": 0.01},
    "mesh": {"edge_length": 0.15},
    "solids": [{"name": "box", "geometry": {"type": "box", "size": [0.3, 0.3, 0.3]},
                "material": {"density": 1000, "youngs_modulus": 1e5, "poissons_ratio": 0.3}}]
  })");
}

/// A ball in a closed box of water (coupled runner), coarse.
json coupled_scene() {
  return json::parse(R"({
    "simulation": {"end_time": 0.01, "dt": 0.005, "frame_rate": 100},
    "domain": {"lo": [-0.4, -0.4, -0.4], "hi": [0.4, 0.4, 0.4]},
    "mesh": {"edge_length": 0.2, "edge_length_near_solids": 0.08, "grading_distance": 0.2},
    "fluid": {"type": "liquid"},
    "solids": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.15, "subdivisions": 2},
                "material": {"density": 500, "youngs_modulus": 1e6, "poissons_ratio": 0.3}}],
    "coupling": {"scheme": "simultaneous"}
  })");
}

struct Result {
  int status = -1;
  std::string out;
};

/// Runs tetfsi in `cwd` under a 60 s limit (a hang shows as status 124, a signal as 128 + n).
Result tetfsi_in(const fs::path& cwd, const std::string& args) {
  Result r;
  r.out = tetfsi::test::run_command("cd '" + cwd.string() + "' && timeout -s KILL 60 " + TETFSI_BINARY + " " + args +
                                        " 2>&1",
                                    &r.status);
  return r;
}

std::string write(const fs::path& dir, const std::string& name, const json& s) {
  const fs::path p = dir / (name + ".json");
  std::ofstream(p) << s.dump(1);
  return p.string();
}

/// validate and run (tiny end time) both exit 2, naming `fragment`; nothing is written in `dir`
/// but the scene, the output folder and the files the case made.
void expect_refused(const fs::path& dir, const std::string& scene, const std::string& fragment,
                    const std::string& end_time = " --end-time 1e-3") {
  SCOPED_TRACE(scene);
  const auto before = std::distance(fs::directory_iterator(dir), fs::directory_iterator());
  const Result v = tetfsi_in(dir, "validate " + scene + end_time);
  const Result r = tetfsi_in(dir, "run " + scene + " --out out --quiet --threads 1" + end_time);
  EXPECT_EQ(v.status, 2) << v.out;
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(v.out.find(fragment), std::string::npos) << v.out;
  EXPECT_NE(r.out.find(fragment), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
  fs::remove_all(dir / "out");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), before)
      << "a file appeared in the working directory (CGAL dump-bug.*?)";
}

struct Case {
  std::string name;
  std::function<json()> scene;
  std::string fragment;  ///< "<name>.json: <pointer>" or the file the message must name
};

void expect_all_refused(const std::vector<Case>& cases, const std::string& end_time = " --end-time 1e-3") {
  tetfsi::test::TempDir dir("bad_inputs");
  for (const auto& c : cases) {
    const std::string file = write(dir.path(), c.name, c.scene());
    expect_refused(dir.path(), file, c.fragment.empty() ? c.name + ".json" : c.name + ".json: " + c.fragment, end_time);
    fs::remove(file);
  }
}

}  // namespace

/// Liquid in a sphere container inside the domain box, around a small ball (fluid runner).
json container_scene() {
  return json::parse(R"({
    "simulation": {"end_time": 0.01, "dt": 0.005, "frame_rate": 100},
    "domain": {"lo": [-0.4, -0.4, -0.4], "hi": [0.4, 0.4, 0.4],
               "container": {"type": "sphere", "center": [0, 0, 0], "radius": 0.35}},
    "mesh": {"edge_length": 0.1},
    "fluid": {"type": "liquid"},
    "solids": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.1, "subdivisions": 1},
                "motion": {"type": "translation", "velocity": [0, 0, 0]},
                "material": {"density": 500, "youngs_modulus": 1e6, "poissons_ratio": 0.3}}]
  })");
}

/// A container_scene whose container is the surface file `file` (absolute path).
json mesh_container_scene(const fs::path& file) {
  json s = container_scene();
  s["domain"]["container"] = {{"type", "mesh"}, {"file", file.string()}};
  return s;
}

/// The OBJ text of the cube [-a, a]^3, outward triangles; `faces` of its 6 faces (fewer: an open box).
std::string cube_obj(double a, int faces = 6) {
  std::string obj;
  for (int i = 0; i < 8; ++i)
    obj += "v " + std::to_string(i & 1 ? a : -a) + " " + std::to_string(i & 2 ? a : -a) + " " +
           std::to_string(i & 4 ? a : -a) + "\n";
  const char* quads[6] = {"1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"};
  for (int f = 0; f < faces; ++f) {
    int q[4];
    std::sscanf(quads[f], "%d %d %d %d", &q[0], &q[1], &q[2], &q[3]);
    obj += "f " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + "\n";
    obj += "f " + std::to_string(q[0]) + " " + std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
  }
  return obj;
}

TEST(BadInputs, ContainersFromSurfaceFilesThatCannotHoldTheFluidAreRefused) {
  tetfsi::test::TempDir files("bad_container_files");
  const fs::path cube = files.path() / "cube.obj", open = files.path() / "open.obj", empty = files.path() / "empty.obj";
  std::ofstream(cube) << cube_obj(0.3);
  std::ofstream(open) << cube_obj(0.3, 5);
  std::ofstream(empty) << "";
  expect_all_refused({
      {"mesh_container_missing", [&] { return mesh_container_scene(files.path() / "nowhere.obj"); },
       "/domain/container/file"},
      {"mesh_container_open", [&] { return mesh_container_scene(open); }, "/domain/container/file"},
      {"mesh_container_empty", [&] { return mesh_container_scene(empty); }, "/domain/container/file"},
      {"mesh_container_no_file", [&] { auto s = mesh_container_scene(cube); s["domain"]["container"].erase("file"); return s; },
       "/domain/container/file"},
      {"mesh_container_scale_0", [&] { auto s = mesh_container_scene(cube); s["domain"]["container"]["unit_scale"] = 0; return s; },
       "/domain/container/unit_scale"},
      {"mesh_container_outside_box",
       [&] { auto s = mesh_container_scene(cube); s["domain"]["container"]["translation"] = {0.2, 0, 0}; return s; },
       "/domain/container"},
      {"mesh_container_below_edge",
       [&] { auto s = mesh_container_scene(cube); s["domain"]["container"]["unit_scale"] = 0.1; s["solids"] = json::array(); return s; },
       "/domain/container"},
      {"mesh_container_open_face", [&] { auto s = mesh_container_scene(cube); s["domain"]["open_faces"] = {"y+"}; return s; },
       "/domain/open_faces"},
      {"solid_outside_mesh_container",
       [&] { auto s = mesh_container_scene(cube); s["solids"][0]["placement"]["translation"] = {0.25, 0, 0}; return s; },
       "/solids/0/placement"},
      {"open_patch_inverted",
       [&] { auto s = mesh_container_scene(cube); s["domain"]["open_patches"] = {{{"lo", {0, 0.3, 0}}, {"hi", {-0.1, 0.31, 0.1}}}}; return s; },
       "/domain/open_patches/0"},
      {"open_patch_no_hi",
       [&] { auto s = mesh_container_scene(cube); s["domain"]["open_patches"] = {{{"lo", {0, 0.3, 0}}}}; return s; },
       "/domain/open_patches/0/hi"},
      {"inflow_profile_unknown",
       [&] {
         auto s = mesh_container_scene(cube);
         s["domain"]["inflows"] = {{{"lo", {-0.1, -0.31, -0.1}}, {"hi", {0.1, -0.29, 0.1}}, {"velocity", {0, 1, 0}},
                                    {"profile", "cubic"}}};
         return s; },
       "/domain/inflows/0/profile"},
  });
}

TEST(BadInputs, ContainersThatCannotHoldTheFluidAreRefused) {
  expect_all_refused({
      {"container_radius_0", [] { auto s = container_scene(); s["domain"]["container"]["radius"] = 0; return s; },
       "/domain/container/radius"},
      {"container_shape", [] { auto s = container_scene(); s["domain"]["container"]["type"] = "cone"; return s; },
       "/domain/container/type"},
      {"container_outside_box", [] { auto s = container_scene(); s["domain"]["container"]["center"] = {0.2, 0, 0}; return s; },
       "/domain/container"},
      {"container_open_face", [] { auto s = container_scene(); s["domain"]["open_faces"] = {"z+"}; return s; },
       "/domain/open_faces"},
      {"solid_outside_container",
       [] { auto s = container_scene(); s["solids"][0]["placement"]["translation"] = {0.28, 0.28, 0}; return s; },
       "/solids/0/placement"},
      {"container_below_edge", [] { auto s = container_scene(); s["domain"]["container"]["radius"] = 0.05; s["solids"] = json::array(); return s; },
       "/domain/container/radius"},
      {"cylinder_no_length", [] {
         auto s = container_scene();
         s["domain"]["container"] = {{"type", "cylinder"}, {"center", {0, 0, 0}}, {"radius", 0.3}};
         return s; }, "/domain/container/length"},
      {"cylinder_axis_w", [] {
         auto s = container_scene();
         s["domain"]["container"] = {{"type", "cylinder"}, {"center", {0, 0, 0}}, {"radius", 0.3}, {"length", 0.6}, {"axis", "w"}};
         return s; }, "/domain/container/axis"},
  });
}

TEST(BadInputs, CoordinatesAndSizesOutOfRangeAreRefusedBeforeMeshing) {
  expect_all_refused({
      {"domain_lo_1e300", [] { auto s = coupled_scene(); s["domain"]["lo"][0] = -1e300; return s; }, "/domain/lo"},
      {"domain_lo_y_9e18", [] { auto s = coupled_scene(); s["domain"]["lo"][1] = -9223372036854775809.0; return s; },
       "/domain/lo"},
      {"translation_1e15", [] { auto s = solid_scene(); s["solids"][0]["placement"]["translation"] = {1e15, 0.65, 0}; return s; },
       "/solids/0/placement/translation"},
      {"translation_1e13", [] { auto s = solid_scene(); s["solids"][0]["placement"]["translation"] = {1e13, 0, 0}; return s; },
       "/solids/0/placement/translation"},
      {"edge_1e-320", [] { auto s = solid_scene(); s["mesh"]["edge_length"] = 1e-320; return s; }, "/mesh/edge_length"},
      {"huge_box", [] { auto s = solid_scene(); s["solids"][0]["geometry"]["size"] = {1e30, 1e30, 1e30}; return s; },
       "/solids/0/geometry"},
  });
}

// Runaways of issue 18 (each ran for minutes or until bad_alloc): refused at once with the
// estimate and the key to change, by validate and run alike (no --end-time override here).
TEST(BadInputs, RunawayResourcesAreRefusedWithTheEstimate) {
  expect_all_refused(
      {
          {"edge_1e-5", [] { auto s = solid_scene(); s["mesh"]["edge_length"] = 1e-5; return s; },
           "/mesh/edge_length: the mesh would have about"},
          {"fine_fluid", [] {
             auto s = coupled_scene();
             s["mesh"]["edge_length"] = 2e-3;
             s["mesh"]["edge_length_near_solids"] = 1e-3;
             return s;
           },
           "/mesh/edge_length: the mesh would have about"},
          {"thin_sheet",
           [] { auto s = solid_scene(); s["solids"][0]["geometry"]["size"] = {1.0, 1e-7, 0.1}; return s; },
           "/solids/0/geometry: the mesh would have about"},
          {"dt_1e-300", [] { auto s = solid_scene(); s["simulation"]["dt"] = 1e-300; return s; },
           "/simulation/dt: the run would take at least"},
          {"end_1e300", [] { auto s = solid_scene(); s["simulation"]["end_time"] = 1e300; return s; },
           "/simulation/dt: the run would take at least"},
          {"frame_rate_1e9", [] { auto s = solid_scene(); s["simulation"]["frame_rate"] = 1e9; return s; },
           "/simulation/frame_rate: the run would take at least"},
          {"hex_cells", [] {
             auto s = solid_scene();
             s["solids"][0]["model"] = {{"type", "hex8"}, {"nx", 2000}, {"ny", 2000}, {"nz", 2000}};
             return s;
           }, "/solids: the mesh would have about 8e+09"},
          {"output_gb", [] {
             auto s = solid_scene();
             s["simulation"]["end_time"] = 10;
             s["simulation"]["frame_rate"] = 100;
             s["export"] = {{"max_output_gb", 1e-6}};
             return s;
           }, "/simulation/frame_rate: the output would take about"},
      },
      "");
  // --max-tets lowers the limit; the default one is named.
  tetfsi::test::TempDir dir("max_tets");
  const std::string scene = write(dir.path(), "small", solid_scene());
  expect_refused(dir.path(), scene + " --max-tets 10", "small.json: /mesh/edge_length: the mesh would have about");
  const Result ok = tetfsi_in(dir.path(), "validate " + scene);
  EXPECT_EQ(ok.status, 0) << ok.out;
}

TEST(BadInputs, BrokenPlySurfacesAreRefusedBeforeAssimpSeesThem) {
  tetfsi::test::TempDir dir("bad_ply");
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  const std::map<std::string, std::string> files = {
      {"header_only.ply", "ply\nformat ascii 1.0\n"},  // assimp looped forever
      {"cut_in_vertices.ply", header + "-0.15 -0.15 -0.15\n-0.15 -0.15 0.15\n-0.15 0.15 -0.15\n0.1"},  // assimp aborted
      {"cut_in_header.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproper"},
  };
  for (const auto& [name, content] : files) {
    std::ofstream(dir.path() / name) << content;
    auto s = solid_scene();
    s["solids"][0]["geometry"] = {{"type", "mesh"}, {"file", name}};
    const std::string scene = write(dir.path(), "scene", s);
    expect_refused(dir.path(), scene, name);
    const Result m = tetfsi_in(dir.path(), "mesh " + name + " out.vtu");
    EXPECT_EQ(m.status, 2) << m.out;
    EXPECT_NE(m.out.find(name + ": PLY"), std::string::npos) << m.out;
  }
}

TEST(BadInputs, FifoAndDeviceScenesAreRefusedWithoutReading) {
  tetfsi::test::TempDir dir("fifo");
  const fs::path fifo = dir.path() / "scene.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused(dir.path(), fifo.string(), "not a regular file");
  fs::remove(fifo);
  expect_refused(dir.path(), "/dev/zero", "not a regular file");
}

TEST(BadInputs, NamesAreSafeForFilesAndCsv) {
  expect_all_refused({
      {"solid_named_fluid", [] { auto s = solid_scene(); s["solids"][0]["name"] = "fluid"; return s; }, "/solids/0/name"},
      {"solid_named_stats_csv", [] { auto s = solid_scene(); s["solids"][0]["name"] = "stats.csv"; return s; },
       "/solids/0/name"},
      {"solid_name_300", [] { auto s = solid_scene(); s["solids"][0]["name"] = std::string(300, 'a'); return s; },
       "/solids/0/name"},
      {"probe_a_comma_b",
       [] { auto s = solid_scene(); s["probes"] = {{{"name", "a,b"}, {"kind", "total_energy"}}}; return s; },
       "/probes/0/name"},
      {"duplicate_probes",
       [] {
         auto s = solid_scene();
         s["probes"] = {{{"name", "e"}, {"kind", "total_energy"}}, {{"name", "e"}, {"kind", "total_energy"}}};
         return s;
       },
       "/probes/1/name"},
      {"threads_1e19", [] { auto s = solid_scene(); s["simulation"]["threads"] = 1e19; return s; }, "/simulation/threads"},
  });
}

// (Kinematic and deformable solids together with a fluid run in the coupled runner:
// CoupledRun.KinematicPaddleAndDeformableFlapRunCoupled.)
TEST(BadInputs, UnsupportedMixesAndProbesAreRefused) {
  expect_all_refused({
      {"solid_inside_the_wall_film",  // the coupled runner would push it off the walls in its first step
       [] {
         auto s = coupled_scene();
         s["coupling"]["contact_gap"] = 10.0;
         return s;
       },
       "/coupling/contact_gap"},
      {"contact_gap_wider_than_the_domain_with_a_fixed_solid",  // no solid moves, the film still fills the box
       [] {
         auto s = coupled_scene();
         s["coupling"]["contact_gap"] = 10.0;
         s["solids"][0]["fixed_regions"] = {{{"lo", {-100, -100, -100}}, {"hi", {100, 100, 100}}}};
         return s;
       },
       "/coupling/contact_gap"},
      {"contact_gap_without_any_contact",  // a film that no contact keeps: contradictory keys
       [] {
         auto s = coupled_scene();
         s["coupling"]["contact_gap"] = 0.01;
         s["coupling"]["wall_contact"] = false;
         return s;
       },
       "/coupling/contact_gap"},
      {"self_contact_on_a_kinematic_solid",  // it deforms nothing, so it cannot fold onto itself
       [] {
         auto s = solid_scene();
         s["solids"][0]["motion"] = {{"type", "translation"}, {"velocity", {0, 0.1, 0}}};
         s["solids"][0]["self_contact"] = true;
         return s;
       },
       "/solids/0/self_contact"},
      {"self_contact_in_a_static_analysis",
       [] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "tet_fem"}, {"analysis", "static"}};
         s["solids"][0]["self_contact"] = true;
         return s;
       },
       "/solids/0/self_contact"},
      {"self_contact_not_a_bool", [] { auto s = solid_scene(); s["solids"][0]["self_contact"] = "yes"; return s; },
       "/solids/0/self_contact"},
      {"cylinder_zero_radius",
       [] {
         auto s = solid_scene();
         s["solids"][0]["geometry"] = {{"type", "cylinder"}, {"radius", 0.0}, {"length", 0.1}};
         return s;
       },
       "/solids/0/geometry/radius"},
      {"cylinder_without_length",
       [] {
         auto s = solid_scene();
         s["solids"][0]["geometry"] = {{"type", "cylinder"}, {"radius", 0.1}};
         return s;
       },
       "/solids/0/geometry/length"},
      {"fluid_force_of_an_unknown_solid",
       [] {
         auto s = coupled_scene();
         s["probes"] = {{{"name", "f"}, {"kind", "fluid_force"}, {"solid", "nobody"}}};
         return s;
       },
       "/probes/0/solid"},
      {"fluid_force_in_a_solid_only_scene",
       [] {
         auto s = solid_scene();
         s["probes"] = {{{"name", "f"}, {"kind", "fluid_force"}, {"solid", s["solids"][0]["name"]}}};
         return s;
       },
       "/probes/0"},
      {"solid_contact_not_a_bool", [] { auto s = coupled_scene(); s["coupling"]["solid_contact"] = 1; return s; },
       "/coupling/solid_contact"},
      {"kinematic_and_deformable_alone",
       [] {
         auto s = solid_scene();
         auto k = s["solids"][0];
         k["name"] = "mover";
         k["placement"]["translation"] = {1, 0, 0};
         k["motion"] = {{"type", "translation"}, {"velocity", {0, 0.1, 0}}};
         s["solids"].push_back(k);
         return s;
       },
       "/solids"},
      {"hex_dynamic_displacement",  // run refused it, validate passed (scripts/bad_inputs.py)
       [] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "hex8"}, {"analysis", "dynamic"}};
         s["solids"][0]["boundary_conditions"] = {{{"type", "displacement"},
                                                   {"box", {{"lo", {-1, -1, -1}}, {"hi", {1, 1, -0.1}}}},
                                                   {"value", {0, 0, 0.01}}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/type"},
      // validate passed these and run refused them (issue 16): now both refuse them before meshing.
      // A rotated hex8 block runs; a world box that held an edge of the unrotated block holds no
      // node of the rotated one.
      {"hex_rotated_region_misses",
       [] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "hex8"}};
         s["solids"][0]["placement"]["rotation_deg"] = {30, 0, 0};
         s["solids"][0]["fixed_regions"] = {{{"lo", {-1, 0.14, 0.14}}, {"hi", {1, 0.16, 0.16}}}};
         return s;
       },
       "/solids/0/fixed_regions/0: the box holds no node of the placed mesh of solid 'box'"},
      {"hex_surface_mesh",
       [] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "hex8"}};
         s["solids"][0]["geometry"] = {{"type", "sphere"}, {"radius", 0.2}};
         return s;
       },
       "/solids/0/model/type: expected \"tet_fem\": `hex8` needs a box or volume_mesh geometry"},
      {"hex_static_and_dynamic",
       [] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "hex8"}};
         auto b = s["solids"][0];
         b["name"] = "box2";
         b["placement"]["translation"] = {1, 0, 0};
         b["model"]["analysis"] = "static";
         s["solids"].push_back(b);
         return s;
       },
       "/solids: hex8 solids ('box', 'box2')"},
      {"sphere_larger_than_box",
       [] { auto s = coupled_scene(); s["solids"][0]["geometry"]["radius"] = 0.6; return s; },
       "/solids/0/placement: solid 'ball'"},
      {"sphere_outside_box",
       [] { auto s = coupled_scene(); s["solids"][0]["placement"]["translation"] = {0.5, 0, 0}; return s; },
       "/solids/0/placement: solid 'ball'"},
      {"sphere_inside_sphere",
       [] {
         auto s = coupled_scene();
         s["solids"][0]["geometry"]["radius"] = 0.3;
         auto k = s["solids"][0];
         k["name"] = "inner";
         k["geometry"]["radius"] = 0.1;
         s["solids"].push_back(k);
         return s;
       },
       "/solids/1/placement: solids 'ball' and 'inner' overlap"},
      {"sphere_in_shell_cavity",
       [] {
         auto s = coupled_scene();
         s["solids"][0]["geometry"] = {{"type", "sphere_shell"}, {"radius", 0.3}, {"thickness", 0.05}, {"subdivisions", 2}};
         auto k = s["solids"][0];
         k["name"] = "inner";
         k["geometry"] = {{"type", "sphere"}, {"radius", 0.1}, {"subdivisions", 2}};
         s["solids"].push_back(k);
         return s;
       },
       "/solids/1/placement: solids 'ball' and 'inner' overlap"},
      {"fluid_probe_in_solid_scene",
       [] { auto s = solid_scene(); s["probes"] = {{{"name", "ke"}, {"kind", "fluid_kinetic_energy"}}}; return s; },
       "/probes/0/kind"},
  });
}

// Liquid regions that hold no liquid (issue 41): validate passed them; run then stopped after
// meshing ("the level set holds no liquid") or, with another region beside them, ran without them.
// A 3 mm sheet next to 3 cm tets, its edges not kept sharp, collapses into slivers in the joint
// fluid-solid mesh (mesh::build_complex refuses it). validate does not mesh, so only run sees it:
// exit 2, the solid named as the scene names it, no internal error.
TEST(BadInputs, ASheetThatCollapsesInTheJointMeshStopsTheRunNamingIt) {
  tetfsi::test::TempDir dir("bad_inputs_sheet");
  json s = coupled_scene();
  s["mesh"] = {{"edge_length", 0.12}, {"edge_length_near_solids", 0.03}, {"grading_distance", 0.2},
               {"feature_angle_deg", 0}};
  s["solids"][0]["name"] = "deflector";
  s["solids"][0]["geometry"] = {{"type", "sheet"}, {"size", {0.36, 0.3}}, {"thickness", 0.003}};
  const Result r = tetfsi_in(dir.path(), "run " + write(dir.path(), "sheet", s) + " --out out --quiet --threads 1");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("solid 'deflector' (/solids/0): its tets hold"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
}

TEST(BadInputs, LiquidRegionsThatHoldNoLiquidAreRefused) {
  const auto regions = [](const json& r) {
    auto s = container_scene();
    s["fluid"]["fill"] = "regions";
    s["fluid"]["regions"] = r;
    return s;
  };
  const json pool = {{"type", "below"}, {"height", 0}};
  expect_all_refused({
      {"liquid_region_outside_the_domain",
       [&] { return regions({{{"type", "box"}, {"lo", {1, 1, 1}}, {"hi", {2, 2, 2}}}}); },
       "/fluid/regions/0: the region lies outside the domain box"},
      {"liquid_region_outside_the_container",  // a corner of the box, outside the sphere
       [&] { return regions({{{"type", "box"}, {"lo", {0.3, 0.3, 0.3}}, {"hi", {0.4, 0.4, 0.4}}}}); },
       "/fluid/regions/0: the region lies outside the sphere container"},
      {"liquid_region_inside_a_solid",
       [&] { return regions({pool, {{"type", "sphere"}, {"center", {0, 0.02, 0}}, {"radius", 0.05}}}); },
       "/fluid/regions/1: the region lies inside solid 'ball'"},
      {"liquid_region_below_the_floor",
       [&] { return regions({{{"type", "below"}, {"height", -0.5}}}); },
       "/fluid/regions/0: the region holds no liquid"},
      {"liquid_cap_below_its_sphere",
       [&] { return regions({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.2}, {"cap_height", -0.3}}}); },
       "/fluid/regions/0: the region holds no liquid"},
      {"no_liquid_regions", [&] { return regions(json::array()); }, "/fluid/regions: fill \"regions\" needs"},
      {"one_of_two_liquid_regions_outside",
       [&] { return regions({pool, {{"type", "box"}, {"lo", {1, 1, 1}}, {"hi", {2, 2, 2}}}}); },
       "/fluid/regions/1: the region lies outside the domain box"},
  });
}

TEST(BadInputs, FluidProbesWorkInACoupledScene) {
  tetfsi::test::TempDir dir("coupled_probes");
  auto s = coupled_scene();
  s["probes"] = {{{"name", "ke"}, {"kind", "fluid_kinetic_energy"}},
                 {{"name", "p_low"}, {"kind", "fluid_point"}, {"point", {0.3, -0.3, 0}}, {"quantity", "pressure"}},
                 {{"name", "p_high"}, {"kind", "fluid_point"}, {"point", {0.3, 0.3, 0}}, {"quantity", "pressure"}}};
  const std::string scene = write(dir.path(), "probes", s);
  const Result r = tetfsi_in(dir.path(), "run " + scene + " --out out --quiet --threads 1");
  ASSERT_EQ(r.status, 0) << r.out;
  const auto csv = tetfsi::test::read_csv(dir.path() / "out" / "probes.csv");
  ASSERT_GE(csv.rows.size(), 2u);
  const std::size_t last = csv.rows.size() - 1;
  // The light ball (500 kg/m^3) starts rising through still water: the fluid gains kinetic energy.
  EXPECT_EQ(csv.at(0, "ke"), 0.0);
  EXPECT_GT(csv.at(last, "ke"), 0.0);
  // Hydrostatics between two points 0.6 m apart: p_low - p_high = rho g dh = 5886 Pa. Linear
  // pressure represents it exactly; the ball's acceleration adds a dynamic part of a few percent.
  EXPECT_NEAR(csv.at(last, "p_low") - csv.at(last, "p_high"), 1000 * 9.81 * 0.6, 0.05 * 5886);
}

TEST(BadInputs, WarningsForIneffectiveEmittersAndOverlappingSolids) {
  tetfsi::test::TempDir dir("warnings");
  auto s = coupled_scene();
  s["fluid"] = {{"type", "smoke"}};
  s["solids"] = json::array();
  s["emitters"] = {{{"shape", {{"type", "box"}, {"lo", {5, 5, 5}}, {"hi", {6, 6, 6}}}}}};
  Result v = tetfsi_in(dir.path(), "validate " + write(dir.path(), "emitter", s));
  EXPECT_EQ(v.status, 0) << v.out;
  EXPECT_NE(v.out.find("warning: /emitters/0/shape: the emitter lies outside the domain"), std::string::npos) << v.out;

  auto t = solid_scene();
  t["solids"].push_back(t["solids"][0]);
  t["solids"][1]["name"] = "box2";
  t["solids"][1]["placement"]["translation"] = {0.1, 0, 0};
  v = tetfsi_in(dir.path(), "validate " + write(dir.path(), "overlap", t));
  EXPECT_EQ(v.status, 0) << v.out;
  EXPECT_NE(v.out.find("warning: /solids/1/placement: solids 'box' and 'box2' overlap"), std::string::npos) << v.out;
}

TEST(BadInputs, UnknownVtuCompressionIsRefused) {
  auto with = [](json value) {
    return [value] {
      json s = solid_scene();
      s["export"]["compression"] = value;
      return s;
    };
  };
  expect_all_refused({{"bogus", with("bogus"), "/export/compression"},
                      {"number", with(1), "/export/compression"}});
}

TEST(BadInputs, HugeUnknownKeyIsNotEchoedWhole) {
  tetfsi::test::TempDir dir("huge_key");
  auto s = solid_scene();
  s[std::string(1 << 20, 'k')] = 1;
  const Result v = tetfsi_in(dir.path(), "validate " + write(dir.path(), "key", s));
  EXPECT_EQ(v.status, 2);
  EXPECT_NE(v.out.find("unknown key"), std::string::npos) << v.out.substr(0, 500);
  EXPECT_LT(v.out.size(), 4000u);
}

// The output folder (apps/run/output.hpp): orphan *.tmp.<pid> files of a killed run are removed
// at the start of a run; a rerun removes the earlier run's frames, .pvd and CSV files (a shorter
// run left stale frames beside its .pvd), and keeps every other file.
TEST(BadInputs, RerunCleansOrphansAndStaleFramesButKeepsOtherFiles) {
  tetfsi::test::TempDir dir("output_folder");
  const fs::path out = dir.path() / "out";
  auto s = solid_scene();
  s["solids"][0]["motion"] = {{"type", "translation"}, {"velocity", {0.1, 0, 0}}};  // kinematic: no meshing
  s["simulation"] = {{"end_time", 0.2}, {"dt", 0.05}, {"frame_rate", 10}};
  const std::string scene = write(dir.path(), "short", s);
  for (const auto& d : {out / "box", out / "old", out / "surfaces"}) fs::create_directories(d);
  for (const auto& f : {out / "run.log", out / "old.pvd", out / "old" / "old_00000.vtu", out / "box" / "box_00007.vtu",
                        out / "surfaces" / "box_00007.ply", out / "box" / "box_00001.vtu.tmp.4242",
                        out / "stats.csv.tmp.17", out / "notes.txt", out / "box" / "mine.txt"})
    std::ofstream(f) << "x";
  const Result r = tetfsi_in(dir.path(), "run " + scene + " --out out --quiet");
  ASSERT_EQ(r.status, 0) << r.out;
  for (const auto& gone : {out / "old.pvd", out / "old", out / "box" / "box_00007.vtu", out / "surfaces" / "box_00007.ply",
                           out / "box" / "box_00001.vtu.tmp.4242", out / "stats.csv.tmp.17"})
    EXPECT_FALSE(fs::exists(gone)) << gone;
  for (const auto& kept : {out / "notes.txt", out / "box" / "mine.txt", out / "box" / "box_00002.vtu", out / "box.pvd"})
    EXPECT_TRUE(fs::exists(kept)) << kept;
  EXPECT_FALSE(fs::exists(out / "box" / "box_00003.vtu"));  // frames 0..2 of this run only
}

/// A solid whose tets come from `file` (solid runner).
json volume_mesh_scene(const std::string& file) {
  auto s = solid_scene();
  s["solids"][0]["geometry"] = {{"type", "volume_mesh"}, {"file", file}};
  return s;
}

/// Each case refused by validate and run naming its key and its cause (causes[name]), in `dir`.
void expect_refused_for(const fs::path& dir, const std::vector<Case>& cases, const std::map<std::string, std::string>& causes) {
  for (const auto& c : cases) {
    const std::string file = write(dir, c.name, c.scene());
    expect_refused(dir, file, c.name + ".json: " + c.fragment);
    expect_refused(dir, file, causes.at(c.name));
    fs::remove(file);
  }
}

/// A hex8 solid whose hexes come from `file` (hex runner).
json hex_mesh_scene(const std::string& file) {
  auto s = volume_mesh_scene(file);
  s["solids"][0]["model"] = {{"type", "hex8"}};
  return s;
}

TEST(BadInputs, BadHexMeshFilesAreRefused) {
  tetfsi::test::TempDir dir("bad_hex_mesh");
  using tetfsi::test::write_vtu_ascii;
  // Two unit cubes side by side (x in [0, 2]), the second numbered mirror-wise (bottom and top swapped).
  std::vector<Eigen::Vector3d> p;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) p.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
  auto id = [](int i, int j, int k) { return i + 3 * (j + 2 * k); };
  const std::vector<int> a = {id(0, 0, 0), id(1, 0, 0), id(1, 1, 0), id(0, 1, 0), id(0, 0, 1), id(1, 0, 1), id(1, 1, 1), id(0, 1, 1)};
  std::vector<int> b = a, b_mirrored;
  for (int& v : b) ++v;
  b_mirrored = {b[4], b[5], b[6], b[7], b[0], b[1], b[2], b[3]};
  write_vtu_ascii(dir.path() / "good_hex.vtu", p, {a, b}, {12, 12});
  write_vtu_ascii(dir.path() / "inverted_hex.vtu", p, {a, b_mirrored}, {12, 12});
  write_vtu_ascii(dir.path() / "empty_hex.vtu", p, {}, {});
  write_vtu_ascii(dir.path() / "tets.vtu", p, {{0, 1, 3, 6}}, {10});
  const std::vector<Case> cases = {
      {"hex_inverted", [] { return hex_mesh_scene("inverted_hex.vtu"); }, "/solids/0/geometry/file"},
      {"hex_given_tets", [] { return hex_mesh_scene("tets.vtu"); }, "/solids/0/geometry/file"},
      {"tet_given_hexes", [] { return volume_mesh_scene("good_hex.vtu"); }, "/solids/0/geometry/file"},
      {"hex_missing_file", [] { return hex_mesh_scene("nowhere.msh"); }, "/solids/0/geometry/file"},
      {"hex_empty_mesh", [] { return hex_mesh_scene("empty_hex.vtu"); }, "/solids/0/geometry/file"},
      {"hex_kinematic_file", [] {  // a moving solid is a surface to the kinematic runner: no hex files
         auto s = hex_mesh_scene("good_hex.vtu");
         s["solids"][0]["motion"] = {{"type", "translation"}, {"velocity", {0.1, 0, 0}}};
         return s; }, "/solids/0/geometry/type"},
  };
  const std::map<std::string, std::string> causes = {
      {"hex_inverted", "inverted_hex.vtu: hex 1 is inverted"},
      {"hex_given_tets", "tets.vtu: cell 0 has VTK type 10 with 4 points; only hexahedra (VTK_HEXAHEDRON, type 12"},
      {"tet_given_hexes", "good_hex.vtu: cell 0 has VTK type 12 with 8 points; only tetrahedra"},
      {"hex_missing_file", "file not found: "},
      {"hex_empty_mesh", "empty_hex.vtu: the mesh has no hexahedra"},
      {"hex_kinematic_file", "a \"volume_mesh\" solid runs in the solid runner only"}};
  expect_refused_for(dir.path(), cases, causes);
  // The good file runs (both hexes, the hex runner).
  const std::string good = write(dir.path(), "hex_good", hex_mesh_scene("good_hex.vtu"));
  const Result v = tetfsi_in(dir.path(), "validate " + good + " --end-time 1e-3");
  EXPECT_EQ(v.status, 0) << v.out;
}

TEST(BadInputs, BadVolumeMeshFilesAndComponentsAreRefused) {
  tetfsi::test::TempDir dir("bad_volume_mesh");
  using tetfsi::test::write_vtu_ascii;
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {0.3, 0, 0}, {0, 0.3, 0}, {0, 0, 0.3}, {0.3, 0.3, 0.3}};
  write_vtu_ascii(dir.path() / "triangle.vtu", p, {{0, 1, 2, 3}, {1, 2, 4}}, {10, 5});
  write_vtu_ascii(dir.path() / "inverted.vtu", p, {{0, 1, 2, 3}, {1, 3, 2, 4}}, {10, 10});
  write_vtu_ascii(dir.path() / "degenerate.vtu", {{0, 0, 0}, {0.3, 0, 0}, {0, 0.3, 0}, {0.1, 0.1, 0}}, {{0, 1, 2, 3}}, {10});
  write_vtu_ascii(dir.path() / "empty.vtu", p, {}, {});
  write_vtu_ascii(dir.path() / "apart.vtu", {{0, 0, 0}, {0.3, 0, 0}, {0, 0.3, 0}, {0, 0, 0.3}, {1, 0, 0}, {1.3, 0, 0},
                                            {1, 0.3, 0}, {1, 0, 0.3}}, {{0, 1, 2, 3}, {4, 5, 6, 7}}, {10, 10});
  std::ofstream(dir.path() / "hex.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n"
                                           "4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n$EndNodes\n$Elements\n1\n"
                                           "3 5 2 1 1 1 2 3 4 5 6 7 8\n$EndElements\n";
  std::ofstream(dir.path() / "old.msh") << "$MeshFormat\n4.0 0 8\n$EndMeshFormat\n";
  write_vtu_ascii(dir.path() / "good.vtu", p, {{0, 1, 2, 3}}, {10});
  const std::vector<Case> cases = {
      {"missing_file", [] { return volume_mesh_scene("nowhere.vtu"); }, "/solids/0/geometry/file"},
      {"wrong_cell", [] { return volume_mesh_scene("triangle.vtu"); }, "/solids/0/geometry/file"},
      {"inverted_tet", [] { return volume_mesh_scene("inverted.vtu"); }, "/solids/0/geometry/file"},
      {"degenerate_tet", [] { return volume_mesh_scene("degenerate.vtu"); }, "/solids/0/geometry/file"},
      {"empty_mesh", [] { return volume_mesh_scene("empty.vtu"); }, "/solids/0/geometry/file"},
      {"two_pieces", [] { return volume_mesh_scene("apart.vtu"); }, "/solids/0/geometry/file"},
      {"hex_msh", [] { return volume_mesh_scene("hex.msh"); }, "/solids/0/geometry/file"},
      {"msh_4_0", [] { return volume_mesh_scene("old.msh"); }, "/solids/0/geometry/file"},
      {"component_w", [] {
         auto s = solid_scene();
         s["solids"][0]["fixed_regions"] = {{{"lo", {-1, -1, -1}}, {"hi", {1, 0, 1}}, {"components", {"w"}}}};
         return s; }, "/solids/0/fixed_regions/0/components/0"},
      {"component_twice", [] {
         auto s = solid_scene();
         s["solids"][0]["fixed_regions"] = {{{"lo", {-1, -1, -1}}, {"hi", {1, 0, 1}}, {"components", {"x", "x"}}}};
         return s; }, "/solids/0/fixed_regions/0/components/1"},
      {"components_empty", [] {
         auto s = solid_scene();
         s["solids"][0]["fixed_regions"] = {{{"lo", {-1, -1, -1}}, {"hi", {1, 0, 1}}, {"components", json::array()}}};
         return s; }, "/solids/0/fixed_regions/0/components"},
      {"hex8_driven", [] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "hex8"}};
         s["solids"][0]["fixed_regions"] = {{{"lo", {-1, -1, -1}}, {"hi", {1, 0, 1}}, {"velocity", {0, 0.1, 0}}}};
         return s; }, "/solids/0/fixed_regions/0/velocity"},
      {"coupled_volume_mesh", [] {
         auto s = coupled_scene();
         s["solids"][0]["geometry"] = {{"type", "volume_mesh"}, {"file", "good.vtu"}};
         return s; }, "/solids/0/geometry/type"},
  };
  const std::map<std::string, std::string> causes = {
      {"missing_file", "file not found"}, {"wrong_cell", "cell 1 has VTK type 5"}, {"inverted_tet", "tet 1 is inverted"},
      {"degenerate_tet", "tet 0 is degenerate"}, {"empty_mesh", "no tetrahedra"}, {"two_pieces", "2 separate pieces"},
      {"hex_msh", "element 3 has Gmsh type 5"}, {"msh_4_0", "format version 4.0"}, {"component_w", "\"x\", \"y\", \"z\""},
      {"component_twice", "twice"}, {"components_empty", "non-empty array"},
      {"hex8_driven", "prescribed velocity is for tet_fem solids"},
      {"coupled_volume_mesh", "cannot keep given tets"}};
  expect_refused_for(dir.path(), cases, causes);
}

// The load keys of /solids/i/boundary_conditions and the static analysis (issue 16).
TEST(BadInputs, LoadKeysAndStaticAnalysisAreRefused) {
  const json box = {{"lo", {-1, -1, -1}}, {"hi", {1, 1, 1}}};
  expect_all_refused({
      {"pressure_zero",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["boundary_conditions"] = {{{"type", "pressure"}, {"box", box}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/pressure"},
      {"pressure_not_a_number",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["boundary_conditions"] = {{{"type", "pressure"}, {"box", box}, {"pressure", "high"}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/pressure"},
      {"body_force_zero",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["boundary_conditions"] = {{{"type", "body_force"}, {"box", box}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/value"},
      {"load_type_unknown",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["boundary_conditions"] = {{{"type", "gravity"}, {"box", box}, {"value", {0, -1, 0}}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/type"},
      {"tet_dynamic_rotation",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["boundary_conditions"] = {{{"type", "moment_rotation"}, {"box", box}, {"angle", 0.1}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/type"},
      {"static_with_springs",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "tet_fem"}, {"analysis", "static"}};
         s["solids"][0]["springs"] = {{{"point", {0, 0, 0}}, {"stiffness", 10}}};
         return s;
       },
       "/solids/0/springs"},
      {"static_driven_region",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "tet_fem"}, {"analysis", "static"}};
         s["solids"][0]["fixed_regions"] = {{{"lo", {-1, -1, -1}}, {"hi", {1, -0.1, 1}}, {"velocity", {0, 0.1, 0}}}};
         return s;
       },
       "/solids/0/fixed_regions/0/velocity"},
      {"kinematic_with_loads",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["motion"] = {{"type", "translation"}, {"velocity", {0, 0.1, 0}}};
         s["solids"][0]["boundary_conditions"] = {{{"type", "nodal_force"}, {"box", box}, {"value", {0, -1, 0}}}};
         return s;
       },
       "/solids/0/boundary_conditions"},
      {"coupled_with_loads",
       [&] {
         auto s = coupled_scene();
         s["solids"][0]["boundary_conditions"] = {{{"type", "pressure"}, {"box", box}, {"pressure", 100}}};
         return s;
       },
       "/solids/0/boundary_conditions"},
      {"coupled_static",
       [&] {
         auto s = coupled_scene();
         s["solids"][0]["model"] = {{"type", "tet_fem"}, {"analysis", "static"}};
         return s;
       },
       "/solids/0/model/analysis"},
      {"load_box_misses_solid",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["boundary_conditions"] = {
             {{"type", "nodal_force"}, {"box", {{"lo", {2, 2, 2}}, {"hi", {3, 3, 3}}}}, {"value", {0, -1, 0}}}};
         return s;
       },
       "/solids/0/boundary_conditions/0/box"},
      {"static_total_energy_probe",
       [&] {
         auto s = solid_scene();
         s["solids"][0]["model"] = {{"type", "tet_fem"}, {"analysis", "static"}};
         s["probes"] = {{{"name", "e"}, {"kind", "total_energy"}}};
         return s;
       },
       "/probes/0/kind"},
  });
}
