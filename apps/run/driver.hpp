#pragma once
/// @file driver.hpp
/// `tetfsi run`: loads the scene, picks a runner, steps it to the end time landing on every
/// frame time, checks each step for non-finite values before anything is written, and writes
/// frames, stats.csv, probes.csv and run.log into the output folder.
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

/// Runs a scene: loads it, runs every check of preflight.hpp (the same as `tetfsi validate`),
/// prepares the output folder (output.hpp: orphan temporary files and the frames of an earlier
/// run are removed), then steps the runner. With options.resume, continues the run in out_dir
/// from its newest checkpoint instead (checkpoint.hpp; its frames up to the checkpoint stay).
/// Returns normally on success.
/// @throws scene::SceneError / InputError (exit 2), RunError (exit 1)
void run_scene(const RunOptions& options);

}  // namespace tetfsi::run
