/// @file preflight_models.cpp
/// The part of preflight (preflight.hpp) that checks which solids and models a runner takes
/// together, so that `validate` refuses what `run` would refuse at setup.
#include "apps/run/preflight_models.hpp"

#include <set>

#include <fmt/format.h>

#include "apps/run/solid_params.hpp"

namespace tetfsi::run {

std::vector<scene::Issue> model_mix_issues(const scene::Json& js, const std::string& runner, bool meshes_fluid) {
  std::vector<scene::Issue> issues;
  const auto add = [&issues](std::string pointer, std::string message) {
    issues.push_back({std::move(pointer), std::move(message)});
  };
  const auto& solids = js.at("solids");
  std::vector<std::string> kinematic, deformable, hex;
  for (const auto& s : solids) {
    const auto name = "'" + s.at("name").get<std::string>() + "'";
    if (s.at("motion").at("type") != "none") kinematic.push_back(name);
    else if (s.at("model").at("type") == "hex8") hex.push_back(name);
    else deformable.push_back(name);
  }
  auto list = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  };
  // The hex8 runner runs one analysis for all hex8 solids (hex_runner.cpp): refused here so that
  // validate gives run's verdict before any setup.
  std::set<std::string> hex_analyses;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const auto& s = solids[i];
    if (s.at("motion").at("type") != "none" || s.at("model").at("type") != "hex8") continue;
    hex_analyses.insert(s["model"].at("analysis").get<std::string>());
  }
  // A volume mesh is the solid's FEM mesh as given. The coupled runner meshes fluid and solids in
  // one CGAL Mesh_3 complex, which remeshes every solid from its surface and cannot keep given
  // tets (nor make the fluid conform to their boundary facets); the other runners take no
  // deforming tet solid. So tet volume meshes run in the solid runner only (hex8 volume meshes in
  // the hex runner, whose scenes have no fluid: check below).
  for (std::size_t i = 0; i < solids.size(); ++i)
    if (solids[i].at("geometry").at("type") == "volume_mesh" && runner != "solid" &&
        (solids[i]["model"]["type"] != "hex8" || solids[i]["motion"]["type"] != "none"))
      add(fmt::format("/solids/{}/geometry/type", i),
          fmt::format("solid '{}': a \"volume_mesh\" solid runs in the solid runner only (fluid type \"none\", "
                      "every solid deforming, model \"tet_fem\"); this scene goes to the {} runner{}",
                      solids[i].at("name").get<std::string>(), runner,
                      meshes_fluid ? ", whose fluid mesh must conform to the solid's boundary: the complex mesher "
                                       "(CGAL Mesh_3) remeshes solids from their surfaces and cannot keep given tets; "
                                       "use geometry type \"mesh\" with the boundary surface instead"
                                     : ""));
  for (std::size_t i = 0; i < solids.size(); ++i)
    if (solids[i].at("self_contact").get<bool>() &&
        (solids[i].at("motion").at("type") != "none" || solids[i].at("model").at("type") != "tet_fem"))
      add(fmt::format("/solids/{}/self_contact", i),
          fmt::format("solid '{}': self-contact is for deforming \"tet_fem\" solids (motion \"none\")",
                      solids[i].at("name").get<std::string>()));
    else if (solids[i].at("self_contact").get<bool>() && is_static(solids[i]))
      add(fmt::format("/solids/{}/self_contact", i),
          fmt::format("solid '{}': self-contact acts in dynamic runs only (model.analysis \"dynamic\")",
                      solids[i].at("name").get<std::string>()));
  // Loads and static analysis of tet solids live in the solid runner only (solid_runner.cpp).
  std::set<std::string> tet_analyses;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const auto& s = solids[i];
    if (s.at("motion").at("type") != "none" || s.at("model").at("type") != "tet_fem") continue;
    tet_analyses.insert(s["model"].value("analysis", "dynamic"));
    if (runner == "solid") continue;
    if (!s.at("boundary_conditions").empty())
      add(fmt::format("/solids/{}/boundary_conditions", i),
          fmt::format("solid '{}': boundary conditions of a tet_fem solid need the solid runner (fluid type "
                      "\"none\"); this scene goes to the {} runner", s.at("name").get<std::string>(), runner));
    if (is_static(s))
      add(fmt::format("/solids/{}/model/analysis", i),
          fmt::format("solid '{}': a static analysis needs the solid runner (fluid type \"none\"); this scene goes "
                      "to the {} runner", s.at("name").get<std::string>(), runner));
  }
  if (tet_analyses.size() > 1)
    add("/solids", fmt::format("tet solids ({}) of one scene must all use the same /solids/i/model/analysis (static "
                               "or dynamic)", list(deformable)));
  if (hex_analyses.size() > 1)
    add("/solids", fmt::format("hex8 solids ({}) of one scene must all use the same /solids/i/model/analysis (static "
                               "or dynamic)", list(hex)));
  const std::string name = runner;
  if (!kinematic.empty() && (!deformable.empty() || !hex.empty()) && name != "mpm" && name != "coupled")
    add("/solids", fmt::format("kinematic solids ({}) together with deforming solids ({}) are not supported yet: no "
                               "runner moves the one and deforms the other in one scene; give every solid a /motion "
                               "(kinematic) or none of them",
                               list(kinematic), list(deformable.empty() ? hex : deformable)));
  else if (!hex.empty() && !deformable.empty())
    add("/solids", fmt::format("hex8 solids ({}) together with tet solids ({}) are not supported yet: use one model "
                               "for every solid (/solids/i/model/type)", list(hex), list(deformable)));
  else if (!hex.empty() && meshes_fluid)
    add("/solids", fmt::format("hex8 solids ({}) do not couple to a fluid yet: use model \"tet_fem\" or fluid type "
                               "\"none\"", list(hex)));
  else if (name == "mesh_only" && !solids.empty())
    add("/solids", "no runner simulates this combination of fluid and solids yet");
  return issues;
}

std::vector<scene::Issue> checkpoint_issues(const scene::Scene& scene, const RunnerEntry& runner) {
  if (scene.json.at("export").value("checkpoint_every", 0) <= 0) return {};
  if (runner.checkpoints && runner.checkpoints(scene)) return {};
  return {{"/export/checkpoint_every",
           fmt::format("the {} runner (which runs this scene{}) does not write checkpoints (the coupled, fluid, solid "
                       "(dynamic) and mpm runners do, without fluid.surface_edge_length): set it to 0", runner.name,
                       runner.name == "solid" ? " as a static analysis" : "")}};
}

std::vector<scene::Issue> process_issues(const scene::Json& js, const std::string& runner, int processes) {
  std::vector<scene::Issue> issues;
  if (processes <= 1) return issues;
  if (runner != "fluid" && runner != "coupled") {
    issues.push_back({"", fmt::format("started as {} MPI processes, but the {} runner runs on one: only fluid and "
                                      "coupled scenes distribute their linear solves (run it without mpirun)",
                                      processes, runner)});
    return issues;
  }
  if (js.at("fluid").at("solver").at("type") != "petsc")
    issues.push_back({"/fluid/solver/type", fmt::format("started as {} MPI processes: set it to \"petsc\" (the solver "
                                                        "that spreads the pressure system over the processes), or run "
                                                        "without mpirun", processes)});
  if (runner == "coupled" && js.at("coupling").at("solver") != "schur_cg")
    issues.push_back({"/coupling/solver", fmt::format("started as {} MPI processes: only \"schur_cg\" runs its "
                                                      "preconditioner on the processes (with fluid.solver.type "
                                                      "\"petsc\")", processes)});
  return issues;
}

}  // namespace tetfsi::run
