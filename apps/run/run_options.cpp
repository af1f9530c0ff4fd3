#include "apps/run/run_options.hpp"

#include <cmath>

#include <fmt/format.h>

#include "apps/run/errors.hpp"

namespace tetfsi::run {

scene::Scene load_with_overrides(const RunOptions& opt) {
  scene::Scene scene = scene::load_scene(opt.scene_file);
  if (opt.end_time) {
    if (!(*opt.end_time > 0) || !std::isfinite(*opt.end_time))
      throw InputError(fmt::format("--end-time: expected a finite number > 0, got {}", *opt.end_time));
    scene.json["simulation"]["end_time"] = *opt.end_time;
  }
  if (opt.threads) {
    if (*opt.threads < 0 || *opt.threads > 1024)
      throw InputError(fmt::format("--threads: expected an integer from 0 to 1024, got {}", *opt.threads));
    scene.json["simulation"]["threads"] = *opt.threads;
  }
  if (opt.max_tets && !(*opt.max_tets >= 1))
    throw InputError(fmt::format("--max-tets: expected a number >= 1, got {}", *opt.max_tets));
  return scene;
}

}  // namespace tetfsi::run
