#include "apps/cli/validate_command.hpp"

#include <iostream>

#include <fmt/format.h>

#include "apps/run/preflight.hpp"

namespace tetfsi::cli {

std::string max_tets_help() {
  return fmt::format("Refuse scenes whose mesh is estimated above this many tets (default: half of this machine's "
                     "memory at {:.0f} bytes per tet: {:.3g})", run::kBytesPerTet, run::default_max_tets());
}

CLI::App* add_validate_command(CLI::App& app, ValidateArgs& args) {
  auto* val = app.add_subcommand("validate", "Check a scene file and report every problem (exit 2 if any): the same "
                                             "checks as `run` makes before meshing");
  val->add_option("scene", args.options.scene_file, "Scene file (JSON)")->required();
  val->add_flag("--resolved", args.print_resolved, "Also print the scene with every default filled in");
  args.end_time_option = val->add_option("--end-time", args.end_time, "Check with this end time [s] (as `run --end-time`)");
  args.max_tets_option = val->add_option("--max-tets", args.max_tets, max_tets_help())->check(CLI::PositiveNumber);
  return val;
}

int validate(ValidateArgs& args, int processes) {
  run::RunOptions& opt = args.options;
  if (*args.end_time_option) opt.end_time = args.end_time;
  if (*args.max_tets_option) opt.max_tets = args.max_tets;
  const auto scene = run::load_with_overrides(opt);
  run::PreflightOptions checks;
  checks.max_tets = opt.max_tets;
  checks.processes = processes;
  const auto report = run::preflight(scene, checks);
  for (const auto& w : report.warnings) std::cerr << "warning: " << w << "\n";
  if (args.print_resolved) std::cout << scene.json.dump(2) << "\n";
  std::cout << fmt::format("{}: valid ({} solid(s), fluid: {}; runner {}, about {:.3g} tets, at least {:.3g} steps, "
                           "{:.3g} frames, about {:.3g} GB of output)\n",
                           opt.scene_file.string(), scene["solids"].size(), scene["fluid"]["type"].get<std::string>(),
                           report.runner, report.tets, report.steps, report.frames, report.output_bytes / 1e9);
  return 0;
}

}  // namespace tetfsi::cli
