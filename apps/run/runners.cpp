/// @file runners.cpp
/// The runner registry: what each runner runs (name, accepts, probe kinds, checkpoints), apart
/// from the runners themselves, so that choosing a runner and checking a scene link no solver
/// (`tetfsi validate`, apps/cli/front.cpp); create_simulation (runner_factories.cpp) builds one.
/// To add a runner: write apps/run/<name>_runner.cpp ending with a
/// `std::unique_ptr<Simulation> make_<name>_runner()` function, add its entry below (more specific
/// runners first; mesh_only accepts every scene and stays last) and its factory to
/// runner_factories.cpp.
#include "apps/run/simulation.hpp"
#include "apps/run/solid_params.hpp"
#include "apps/run/surface_refinement.hpp"

namespace tetfsi::run {

bool is_deformable_tet(const scene::Json& solid) {
  return solid.at("motion").at("type") == "none" && solid.at("model").at("type") == "tet_fem";
}

bool is_hex(const scene::Json& s) { return s.at("motion").at("type") == "none" && s.at("model").at("type") == "hex8"; }

bool deforms_as(const scene::Json& solid, const char* model) {
  return solid.at("motion").at("type") == "none" && solid.at("model").at("type") == model;
}

namespace {

RunnerEntry coupled_runner() {
  return {"coupled", "fluid and deformable tet solids in one linear system per step (Chentanez et al. 2006, eq. 7)",
          [](const scene::Scene& scene) {
            const auto& s = scene.json;
            // Fluid, every solid a tet solid, at least one of them deforming (the others kinematic).
            if (s.at("fluid").at("type") == "none" || s.at("solids").empty()) return false;
            bool deforming = false;
            for (const auto& solid : s.at("solids")) {
              if (solid.at("model").at("type") != "tet_fem") return false;
              deforming = deforming || is_deformable_tet(solid);
            }
            return deforming;
          },
          {"point_displacement", "solid_volume", "total_energy", "fluid_volume", "fluid_point", "fluid_kinetic_energy",
           "fluid_force", "contact_force"},
          // Not yet with a free surface's refinement, whose last fit (a copy of that mesh and
          // level set) a checkpoint does not hold.
          [](const scene::Scene& s) { return !surface_refinement(s.json).on(); }};
}

RunnerEntry fluid_runner() {
  return {"fluid",
          "smoke or liquid around static or kinematic solids (moved with them every step, remeshed when the mesh "
          "degrades)",
          [](const scene::Scene& s) {
            if (s.json.contains("mpm")) return false;  // MPM + membranes: the mpm runner
            const auto type = s["fluid"].at("type");
            if (type != "smoke" && type != "liquid") return false;
            for (const auto& solid : s["solids"])
              if (solid.at("motion").at("type") == "none") return false;  // deformable: coupled runner
            return true;
          },
          {"fluid_point", "fluid_kinetic_energy", "fluid_volume", "fluid_force"},
          // Not yet with a free surface's refinement, whose last fit (a copy of that mesh and
          // level set) a checkpoint does not hold.
          [](const scene::Scene& s) { return !surface_refinement(s.json).on(); }};
}

RunnerEntry kinematic_runner() {
  return {"kinematic", "solids following their prescribed motion (no fluid, no deformation)",
          [](const scene::Scene& s) {
            if (s["fluid"].at("type") != "none" || s["solids"].empty()) return false;
            for (const auto& solid : s["solids"])
              if (solid.at("motion").at("type") == "none") return false;
            return true;
          },
          {"point_displacement", "solid_volume"}};
}

RunnerEntry solid_runner() {
  return {"solid", "deformable tet FEM solids without fluid (implicit Newmark integration, contact)",
          [](const scene::Scene& s) {
            if (s["fluid"].at("type") != "none") return false;
            for (const auto& solid : s["solids"])
              if (deforms_as(solid, "tet_fem")) return true;
            return false;
          },
          {"point_displacement", "solid_volume", "total_energy", "contact_force"},
          [](const scene::Scene& s) {  // a static analysis has no time loop to resume
            for (const auto& solid : s["solids"])
              if (is_static(solid)) return false;
            return true;
          }};
}

RunnerEntry hex_runner() {
  return {"hex", "Total Lagrangian hex8 blocks without fluid (static load stepping or implicit Newmark dynamics)",
          [](const scene::Scene& s) {
            if (s["fluid"].at("type") != "none") return false;
            bool any = false;
            for (const auto& solid : s["solids"]) {
              if (solid.at("motion").at("type") == "none" && solid.at("model").at("type") == "tet_fem") return false;
              any = any || is_hex(solid);
            }
            return any;
          },
          {"point_displacement", "total_energy"}};
}

RunnerEntry mpm_runner() {
  return {"mpm", "MPM particles + Belytschko-Tsay membranes with grid contact (Lian, Liu & Zhang 2014)",
          [](const scene::Scene& s) { return s.json.contains("mpm"); },
          {},
          [](const scene::Scene&) { return true; }};
}

RunnerEntry mesh_only_runner() {
  return {"mesh_only", "meshes the scene and exports frame 0 (no physics yet)",
          [](const scene::Scene&) { return true; },
          {"solid_volume"}};
}

}  // namespace

const std::vector<RunnerEntry>& runners() {
  static const std::vector<RunnerEntry> list = {
      coupled_runner(),
      fluid_runner(),
      kinematic_runner(),
      solid_runner(),  // fluid none, a deforming tet solid
      hex_runner(),    // fluid none, deforming hex8 solids only
      mpm_runner(),
      mesh_only_runner(),  // fallback: keep last
  };
  return list;
}

const RunnerEntry& choose_runner(const scene::Scene& scene) {
  for (const auto& r : runners())
    if (r.accepts(scene)) return r;
  return runners().back();
}

}  // namespace tetfsi::run
