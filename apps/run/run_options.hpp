#pragma once
/// @file run_options.hpp
/// The command-line options of `tetfsi run` and `tetfsi validate` and the scene they load. Kept
/// apart from driver.hpp so that `tetfsi validate` (apps/cli/front.cpp) links no solver code.
#include <filesystem>
#include <optional>
#include <string>

#include "apps/scene/scene.hpp"

namespace tetfsi::run {

struct RunOptions {
  std::filesystem::path scene_file;
  std::filesystem::path out_dir = "out";
  std::optional<double> end_time;  ///< overrides /simulation/end_time [s]
  std::optional<int> threads;      ///< overrides /simulation/threads
  bool quiet = false;              ///< no progress line
  std::string command_line;        ///< recorded in run.log
  std::optional<double> max_tets;  ///< --max-tets (default: from the machine's memory, preflight.hpp)
  bool resume = false;             ///< --resume: continue from the newest checkpoint in out_dir (checkpoint.hpp)
};

/// Loads the scene and applies the command-line overrides (--end-time, --threads).
/// @throws scene::SceneError / InputError (exit 2)
scene::Scene load_with_overrides(const RunOptions& options);

}  // namespace tetfsi::run
