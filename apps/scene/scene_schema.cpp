#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

#include <fmt/format.h>

#include "apps/mpm/probes.hpp"
#include "apps/mpm/setup.hpp"
#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene {
namespace {

// Probe kinds of mpm scenes (apps/mpm/probes.hpp).
const std::set<std::string>& mpm_probe_kinds() {
  static const std::set<std::string> kinds = {"membrane_point", "membrane_radius", "membrane_volume", "particle_point",
                                              "body_energy"};
  return kinds;
}

// An mpm scene is particles + membrane only: no tet fluid, no tet solids; its probes are the mpm
// kinds and total_energy; the mpm kinds need an mpm block. Then the problem is built
// (apps/mpm/setup.hpp) as the runner builds it, for what only the geometry shows.
void check_mpm(const Json& s, std::vector<Issue>& issues) {
  const bool mpm = s.contains("mpm");
  if (mpm && s["fluid"]["type"] != "none")
    issues.push_back({"/fluid/type", fmt::format("an mpm scene has its fluid as particles (/mpm); expected "
                                                 "\"none\", got \"{}\"", s["fluid"]["type"].get<std::string>())});
  if (mpm && !s["solids"].empty())
    issues.push_back({"/solids", "an mpm scene has no tet solids (its bodies are /mpm/bodies and /mpm/membrane); "
                                 "expected an empty list"});
  for (std::size_t i = 0; i < s["probes"].size(); ++i) {
    const auto kind = s["probes"][i]["kind"].get<std::string>();
    if (!mpm_probe_kinds().count(kind)) {
      if (mpm && kind != "total_energy")
        issues.push_back({fmt::format("/probes/{}/kind", i),
                          fmt::format("probe kind \"{}\" needs tet solids or a fluid; an mpm scene has \"total_energy\" "
                                      "and the mpm kinds (membrane_point, membrane_radius, membrane_volume, "
                                      "particle_point, body_energy)", kind)});
    } else if (!mpm) {
      issues.push_back({fmt::format("/probes/{}/kind", i),
                        fmt::format("probe kind \"{}\" needs an /mpm block", kind)});
    }
  }
  if (!mpm || !issues.empty()) return;
  try {
    const auto& g = s["simulation"]["gravity"];
    const auto setup = mpm_setup::build_setup(s["mpm"], mpm::Vec3(g[0].get<double>(), g[1].get<double>(), g[2].get<double>()));
    mpm_setup::resolve_probes(setup, s["probes"]);
  } catch (const mpm_setup::SetupError& e) {
    issues.push_back({e.pointer(), e.what()});
  }
}

// A `sphere_shell` has a fluid cavity: only the coupled runner meshes it (a fluid, the shell a
// free tet solid; the other runners refuse it at run time, run/solid_geometry.cpp). `fluid.fill: cavities` needs exactly one shell and no domain.
void check_shells(const Json& s, std::vector<Issue>& issues) {
  int shells = 0;
  for (std::size_t i = 0; i < s["solids"].size(); ++i) {
    const auto& solid = s["solids"][i];
    if (solid["geometry"]["type"] != "sphere_shell") continue;
    ++shells;
    if (s["fluid"]["type"] == "none")
      issues.push_back({fmt::format("/solids/{}/geometry/type", i),
                        "a sphere_shell's cavity is fluid: the scene needs a liquid or smoke fluid (and a "
                        "/coupling block)"});
    else if (solid["model"]["type"] != "tet_fem" || solid["motion"]["type"] != "none")
      issues.push_back({fmt::format("/solids/{}/geometry/type", i),
                        "a sphere_shell must be a deforming tet solid (model tet_fem, motion none)"});
  }
  if (s["fluid"].value("fill", "domain") != "cavities") return;
  if (shells != 1 || s["solids"].size() != 1)
    issues.push_back({"/fluid/fill", fmt::format("\"cavities\" fills the cavity of one solid: expected exactly one "
                                                 "solid, a sphere_shell (got {} solid(s), {} shell(s))",
                                                 s["solids"].size(), shells)});
  if (s.contains("domain"))
    issues.push_back({"/domain", "the fluid fills only the shell's cavity (fluid.fill = \"cavities\"): remove "
                                 "the domain box, nothing outside the shell is meshed"});
}

// `fluid.fill: regions` (a free surface) needs regions that hold liquid in the domain; its solids
// are tet FEM or kinematic.
void check_free_surface(const Json& s, std::vector<Issue>& issues) {
  if (s["fluid"]["type"] != "liquid") return;
  if (s["fluid"].value("fill", "domain") != "regions") {
    if (s["fluid"].value("surface_edge_length", 0.0) > 0)
      issues.push_back({"/fluid/surface_edge_length", "refines at a free surface: needs fluid.fill \"regions\""});
    return;
  }
  // Each region must hold liquid: checked with the container and the solids by the preflight
  // (apps/run/preflight_liquid.hpp).
  if (s["fluid"].value("surface_edge_length", 0.0) > s["mesh"].value("edge_length", 0.1))
    issues.push_back({"/fluid/surface_edge_length", "expected a value <= mesh.edge_length (refinement at the surface, "
                                                    "not coarsening)"});
  if (s["fluid"]["regions"].empty())
    issues.push_back({"/fluid/regions", "fill \"regions\" needs at least one region (box, sphere, below or mesh)"});
  for (std::size_t i = 0; i < s["solids"].size(); ++i) {
    const auto& solid = s["solids"][i];
    if (solid["motion"]["type"] == "none" && solid["model"]["type"] != "tet_fem")
      issues.push_back({fmt::format("/solids/{}/model/type", i),
                        "a liquid with a free surface (fluid.fill \"regions\") couples to deforming tet_fem "
                        "solids (and static or kinematic ones); hex8 solids do not take part in the coupled solve"});
  }
  if (s.contains("coupling") && s["coupling"].value("constraint", "end_of_step") == "step_mean")
    issues.push_back({"/coupling/constraint", "the step-mean constraint does not apply to a free surface "
                                              "(fluid.fill \"regions\"): use \"end_of_step\""});
}

constexpr std::size_t kMaxNameLength = 64;

/// A name that is safe as a file name on every file system and as a CSV column: 1 to 64 of
/// A-Z a-z 0-9 _ -, starting with a letter or digit (no dot, so no "stats.csv" or "..").
bool safe_name(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameLength || name[0] == '-' || name[0] == '_') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string shown(const std::string& name) {
  return name.size() <= kMaxNameLength ? name : name.substr(0, kMaxNameLength) + "...";
}

// Solid names name output files (<name>.pvd, <name>/, surfaces/<name>_*.ply): safe, unique
// without regard to case (case-insensitive file systems), and none of the other objects a run
// writes. Probe names are probes.csv columns: safe, unique after the _x/_y/_z expansion.
void check_names(const Json& s, std::vector<Issue>& issues, std::set<std::string>& names) {
  static const std::set<std::string> reserved = {"fluid", "liquid", "particles", "membrane", "surfaces"};
  std::set<std::string> folded;
  for (std::size_t i = 0; i < s["solids"].size(); ++i) {
    const auto name = s["solids"][i]["name"].get<std::string>();
    const std::string ptr = fmt::format("/solids/{}/name", i);
    if (!safe_name(name))
      issues.push_back({ptr, fmt::format("expected 1 to {} letters, digits, '_' or '-' (starting with a letter or "
                                         "digit; the name is used in output file names), got \"{}\" ({} characters)",
                                         kMaxNameLength, shown(name), name.size())});
    else if (reserved.count(lower(name)))
      issues.push_back({ptr, fmt::format("\"{}\" is the name of another output of a run (fluid, particles, membrane, "
                                         "surfaces): choose another name", name)});
    else if (!folded.insert(lower(name)).second)
      issues.push_back({ptr, fmt::format("duplicate solid name \"{}\" (names are compared without regard to case: "
                                         "they name files)", name)});
    names.insert(name);
  }
  std::set<std::string> columns = {"time"};
  for (std::size_t i = 0; i < s["probes"].size(); ++i) {
    const auto& p = s["probes"][i];
    const auto name = p["name"].get<std::string>();
    const std::string ptr = fmt::format("/probes/{}/name", i);
    if (!safe_name(name)) {
      issues.push_back({ptr, fmt::format("expected 1 to {} letters, digits, '_' or '-' (the name is a probes.csv "
                                         "column), got \"{}\"", kMaxNameLength, shown(name))});
      continue;
    }
    std::vector<std::string> cols = {name};
    if (p["kind"] == "point_displacement") cols = {name + "_x", name + "_y", name + "_z"};
    for (const auto& c : cols)
      if (!columns.insert(lower(c)).second) {
        issues.push_back({ptr, fmt::format("probes.csv would have two columns \"{}\" (probe names must be unique, "
                                           "and differ from \"time\")", c)});
        break;
      }
  }
}

// Checks across blocks: names are safe and unique, probes name existing solids, a fluid needs a domain.
void check_scene(const Json& s, const std::string&, std::vector<Issue>& issues) {
  std::set<std::string> names;
  check_names(s, issues, names);
  for (std::size_t i = 0; i < s["probes"].size(); ++i) {
    const auto& p = s["probes"][i];
    if (p.contains("solid") && !names.count(p["solid"].get<std::string>()))
      issues.push_back({fmt::format("/probes/{}/solid", i),
                        fmt::format("no solid named \"{}\" in /solids", shown(p["solid"].get<std::string>()))});
  }
  check_mpm(s, issues);
  check_shells(s, issues);
  check_free_surface(s, issues);
  if (!s.contains("domain") && s["solids"].empty() && !s.contains("mpm"))
    issues.push_back({"/solids", "the scene has neither a domain nor any solid: nothing to simulate"});
  if (s["fluid"]["type"] != "none" && !s.contains("domain") && s["fluid"].value("fill", "domain") != "cavities")
    issues.push_back({"/domain", fmt::format("missing: a {} fluid needs a domain box {{\"lo\": [...], \"hi\": [...]}}",
                                             s["fluid"]["type"].get<std::string>())});
}

Field build() {
  return Field::object("", "A tetfsi scene.", {
      Field::string("description", "Free text shown in run.log."),
      blocks::simulation().req(),
      blocks::domain(),
      blocks::mesh(),
      blocks::fluid(),
      blocks::solids(),
      blocks::coupling(),
      blocks::obstacles(),
      blocks::emitters(),
      blocks::probes(),
      blocks::output(),
      blocks::mpm(),
  }).check(check_scene);
}

}  // namespace

const Field& scene_schema() {
  static const Field schema = build();
  return schema;
}

}  // namespace tetfsi::scene
