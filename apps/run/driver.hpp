#pragma once
/// @file driver.hpp
/// `tetfsi run`: loads the scene, picks a runner, steps it to the end time landing on every
/// frame time, checks each step for non-finite values before anything is written, and writes
/// frames, stats.csv, probes.csv and run.log into the output folder.
#include <filesystem>
#include <optional>
#include <string>

#include "apps/run/run_options.hpp"
#include "apps/scene/scene.hpp"

namespace tetfsi::run {

/// Runs a scene: loads it, runs every check of preflight.hpp (the same as `tetfsi validate`),
/// prepares the output folder (output.hpp: orphan temporary files and the frames of an earlier
/// run are removed), then steps the runner. With options.resume, continues the run in out_dir
/// from its newest checkpoint instead (checkpoint.hpp; its frames up to the checkpoint stay).
/// Returns normally on success.
/// @throws scene::SceneError / InputError (exit 2), RunError (exit 1)
void run_scene(const RunOptions& options);

}  // namespace tetfsi::run
