/// @file runners.cpp
/// The runner registry. To add a runner: write apps/run/<name>_runner.cpp ending with a
/// `RunnerEntry <name>_runner()` function, and add it to the list below (more specific runners
/// first; mesh_only accepts every scene and stays last).
#include "apps/run/simulation.hpp"

namespace tetfsi::run {

RunnerEntry coupled_runner();
RunnerEntry fluid_runner();
RunnerEntry kinematic_runner();
RunnerEntry solid_runner();
RunnerEntry hex_runner();
RunnerEntry mpm_runner();
RunnerEntry mesh_only_runner();

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
