#include "apps/run/driver.hpp"

#include <cmath>
#include <cstdint>
#include <memory>
#include <set>

#include <fmt/format.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "apps/run/errors.hpp"
#include "apps/run/progress.hpp"
#include "apps/run/simulation.hpp"
#include "support/stopwatch.hpp"
#include "apps/version.hpp"

namespace tetfsi::run {
namespace fs = std::filesystem;
namespace {

std::shared_ptr<spdlog::logger> make_logger(const fs::path& dir) {
  auto file = std::make_shared<spdlog::sinks::basic_file_sink_mt>((dir / "run.log").string(), true);
  file->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
  auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  console->set_level(spdlog::level::warn);
  console->set_pattern("%^%l%$: %v");
  auto log = std::make_shared<spdlog::logger>("run", spdlog::sinks_init_list{file, console});
  log->set_level(spdlog::level::info);
  log->flush_on(spdlog::level::info);
  return log;
}

/// FNV-1a 64-bit hash of a text (to tell runs of identical resolved scenes apart in run.log).
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t hash = 1469598103934665603ull;
  for (unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
  return hash;
}

/// probes.csv column names of one probe.
std::vector<std::string> probe_columns(const scene::Json& p) {
  const auto name = p.at("name").get<std::string>();
  if (p.at("kind") == "point_displacement") return {name + "_x", name + "_y", name + "_z"};
  return {name};
}

/// The state was checked, so writing it is safe.
void write_frame(Simulation& sim, Output& out, int frame, double t) {
  if (out.frame_due(frame)) sim.write_frame(out, frame, t);
}

class Driver {
 public:
  Driver(const RunOptions& opt, scene::Scene scene, spdlog::logger& log)
      : opt_(opt), scene_(std::move(scene)), log_(log) {}

  void run() {
    const auto& entry = choose_runner(scene_);
    log_.info("runner: {}: {}", entry.name, entry.summary);
    if (!opt_.quiet) fmt::print("{}: {}\n", entry.name, entry.summary);
    auto sim = entry.create();
    Output out(opt_.out_dir, scene_["export"]);
    Stopwatch wall;
    sim->setup(scene_, log_);
    log_.info("setup done in {:.3f} s", wall.seconds());

    std::vector<std::string> header = {"step", "time", "dt"};
    for (const auto& p : sim->phases()) header.push_back("t_" + p);
    header.push_back("t_output");
    for (const auto& c : sim->columns()) header.push_back(c);
    out.begin_stats(header);
    const auto& probes = scene_["probes"];
    if (!probes.empty()) {
      std::vector<std::string> ph = {"time"};
      for (const auto& p : probes)
        for (const auto& c : probe_columns(p)) ph.push_back(c);
      out.begin_probes(ph);
    }

    check_finite(*sim, 0, 0.0);
    Stopwatch io;
    write_frame(*sim, out, 0, 0.0);
    double t_output = io.seconds();
    record_probes(*sim, out, 0.0);
    if (!sim->time_dependent()) {
      StepReport r = sim->setup_report();
      std::vector<double> row = {0, 0, 0};
      row.insert(row.end(), r.phase_seconds.begin(), r.phase_seconds.end());
      row.push_back(t_output);
      row.insert(row.end(), r.values.begin(), r.values.end());
      out.stats_row(row);
      log_.info("done: frame 0 written in {:.3f} s (total {:.3f} s)", t_output, wall.seconds());
      return;
    }

    const double end = scene_["simulation"].at("end_time").get<double>();
    const double frame_dt = 1.0 / scene_["simulation"].at("frame_rate").get<double>();
    const double eps = 1e-12 * std::max(end, frame_dt);
    Progress progress(end, !opt_.quiet);
    double t = 0;
    long step = 0;
    int frame = 0;
    try {
      while (t < end - eps) {
        const double next_frame = (frame + 1) * frame_dt;
        const double h_max = sim->max_dt();
        if (!(h_max > 0) || !std::isfinite(h_max))
          throw RunError(fmt::format("step {} (t = {:.6g} s): the model asked for a time step of {} s",
                                     step + 1, t, h_max));
        // A step that reaches the next frame (or the end) within round-off of its largest step
        // lands on it exactly: summing h's otherwise leaves a remainder of ~1e-12 s, and a step
        // that short is a different problem (e.g. A = M/h dominates the coupled solve). Likewise,
        // when a full step would leave less than half a step before the frame (a CFL step that
        // does not divide the frame), the rest is taken in two equal steps instead of a full one
        // and a sliver.
        const double target = std::min(next_frame, end);
        const double remaining = target - t;
        const bool lands = remaining <= h_max * (1 + 1e-9);
        const double h = lands ? remaining : remaining < 1.5 * h_max ? 0.5 * remaining : h_max;
        StepReport r = sim->step(h);
        t = lands && r.dt == h ? target : t + r.dt;
        ++step;
        check_finite(*sim, step, t);
        io.restart();
        if (t >= next_frame - eps) write_frame(*sim, out, ++frame, t);
        record_probes(*sim, out, t);
        t_output = io.seconds();
        std::vector<double> row = {double(step), t, r.dt};
        row.insert(row.end(), r.phase_seconds.begin(), r.phase_seconds.end());
        row.push_back(t_output);
        row.insert(row.end(), r.values.begin(), r.values.end());
        out.stats_row(row);
        progress.update(t, step, wall.seconds());
      }
    } catch (...) {
      progress.interrupt();
      throw;
    }
    progress.finish(t, step, wall.seconds());
    log_.info("done: {} steps, {} frames, simulated {:.6g} s in {:.3f} s of wall time", step, frame + 1,
              t, wall.seconds());
  }

 private:
  void check_finite(const Simulation& sim, long step, double t) {
    const std::string bad = sim.non_finite();
    if (bad.empty()) return;
    throw RunError(fmt::format(
        "step {} (t = {:.6g} s): non-finite value in {}: the simulation diverged. Nothing of this "
        "step was written; earlier frames are intact. Try a smaller time step (simulation.dt or "
        "simulation.cfl) or check the material parameters.",
        step, t, bad));
  }

  void record_probes(const Simulation& sim, Output& out, double t) {
    const auto& probes = scene_["probes"];
    if (probes.empty()) return;
    std::vector<double> row = {t};
    for (std::size_t i = 0; i < probes.size(); ++i) {
      auto values = sim.probe(probes[i]);
      const auto cols = probe_columns(probes[i]);
      if (values.size() != cols.size()) {
        if (warned_.insert(i).second)
          log_.warn("probe /probes/{} ('{}', kind {}) is not supported by this runner; its column is NaN",
                    i, probes[i]["name"].get<std::string>(), probes[i]["kind"].get<std::string>());
        values.assign(cols.size(), std::nan(""));
      }
      row.insert(row.end(), values.begin(), values.end());
    }
    out.probes_row(row);
  }

  const RunOptions& opt_;
  scene::Scene scene_;
  spdlog::logger& log_;
  std::set<std::size_t> warned_;
};

}  // namespace

void run_scene(const RunOptions& opt) {
  scene::Scene scene = scene::load_scene(opt.scene_file);
  if (opt.end_time) {
    if (!(*opt.end_time > 0)) throw InputError(fmt::format("--end-time: expected a number > 0, got {}", *opt.end_time));
    scene.json["simulation"]["end_time"] = *opt.end_time;
  }
  if (opt.threads) {
    if (*opt.threads < 0) throw InputError(fmt::format("--threads: expected an integer >= 0, got {}", *opt.threads));
    scene.json["simulation"]["threads"] = *opt.threads;
  }
  std::error_code ec;
  fs::create_directories(opt.out_dir, ec);
  if (ec || !fs::is_directory(opt.out_dir))
    throw InputError(fmt::format("cannot create the output folder {}: {}", opt.out_dir.string(),
                                 ec ? ec.message() : "not a folder"));
  const bool reused = fs::exists(opt.out_dir / "run.log");
  std::shared_ptr<spdlog::logger> log;
  try {
    log = make_logger(opt.out_dir);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("cannot write run.log in the output folder {}: {}", opt.out_dir.string(), e.what()));
  }
  log->info("tetfsi {}", TETFSI_VERSION);
  if (!opt.command_line.empty()) log->info("command: {}", opt.command_line);
  log->info("scene: {}", fs::absolute(opt.scene_file).string());
  if (reused)
    log->warn("{} holds an earlier run: files with the same names are replaced, other files are kept",
              opt.out_dir.string());
  const int threads = scene["simulation"].at("threads").get<int>();
  const int used = threads > 0 ? threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, used);
  log->info("threads: {}", used);
  const std::string resolved = scene.json.dump(2);
  log->info("resolved scene (defaults filled in; FNV-1a hash {:016x}):\n{}", fnv1a(resolved), resolved);
  try {
    Driver(opt, std::move(scene), *log).run();
  } catch (const std::exception& e) {
    log->sinks().back()->set_level(spdlog::level::off);  // main prints it on the console
    log->error("{}", e.what());
    log->flush();
    throw;
  }
  spdlog::drop("run");
}

}  // namespace tetfsi::run
