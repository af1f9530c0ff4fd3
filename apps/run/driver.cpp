#include "apps/run/driver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/null_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include "apps/run/checkpoint.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/preflight.hpp"
#include "apps/run/progress.hpp"
#include "apps/run/simulation.hpp"
#include "support/stopwatch.hpp"
#include "apps/version.hpp"
#include "parallel/mpi_session.hpp"

namespace tetfsi::run {
namespace fs = std::filesystem;
namespace {

/// run.log in `dir`, started afresh (`truncate`) or continued (a resumed run).
std::shared_ptr<spdlog::logger> make_logger(const fs::path& dir, bool truncate) {
  auto file = std::make_shared<spdlog::sinks::basic_file_sink_mt>((dir / "run.log").string(), truncate);
  file->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
  auto console = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  console->set_level(spdlog::level::warn);
  console->set_pattern("%^%l%$: %v");
  auto log = std::make_shared<spdlog::logger>("run", spdlog::sinks_init_list{file, console});
  log->set_level(spdlog::level::info);
  log->flush_on(spdlog::level::info);
  return log;
}

/// probes.csv column names of one probe.
std::vector<std::string> probe_columns(const scene::Json& p) {
  const auto name = p.at("name").get<std::string>();
  if (p.at("kind") == "point_displacement" || p.at("kind") == "fluid_force" || p.at("kind") == "contact_force")
    return {name + "_x", name + "_y", name + "_z"};
  return {name};
}

class Driver {
 public:
  /// `time_steps`: the run's time step policy (read_time_step_policy of the scene); `resume`: the
  /// checkpoint to continue from (`run --resume`), or null.
  Driver(const RunOptions& opt, scene::Scene scene, const scene::TimeStepPolicy& time_steps, spdlog::logger& log,
         LoadedCheckpoint* resume)
      : opt_(opt), scene_(std::move(scene)), time_steps_(time_steps), log_(log), resume_(resume) {
    checkpoint_every_ = writes_ ? scene_["export"].value("checkpoint_every", 0) : 0;
    scene_hash_ = checkpoint_scene_hash(scene_.json);
  }

  /// Writes frame `frame` if it is due and logs the bytes it took (the state was checked, so
  /// writing it is safe).
  void write_frame(Simulation& sim, Output& out, int frame, double t) {
    if (!writes_ || !out.frame_due(frame)) return;
    const Output::Bytes before = out.bytes_written();
    Stopwatch clock;
    sim.write_frame(out, frame, t);
    const Output::Bytes& after = out.bytes_written();
    ++frames_written_;
    log_.info("frame {} (t = {:.6g} s): {} bytes written (.vtu {}, surfaces {}, volumes {}) in {:.3f} s", frame, t,
              after.total() - before.total(), after.vtu - before.vtu, after.surfaces - before.surfaces,
              after.volumes - before.volumes, clock.seconds());
  }

  /// The run.log line on the frames written in all.
  void log_output_total(const Output& out) {
    if (!writes_) return;
    const Output::Bytes& b = out.bytes_written();
    log_.info("output: {} frame(s), {} bytes of frame files (.vtu {}, surfaces {}, volumes {}), {:.0f} bytes per frame",
              frames_written_, b.total(), b.vtu, b.surfaces, b.volumes,
              frames_written_ ? double(b.total()) / frames_written_ : 0.0);
    if (out.volumes() && b.volumes > 0)
      log_.info("volumes: {} bytes of .vdb files at a voxel size of {:.6g} m", b.volumes, out.fixed_voxel_size());
    if (const auto& scale = out.surface_scale(); out.smooth_liquid_surface() && scale.voxel_size > 0)
      log_.info("liquid surface: smooth, voxel size {:.6g} m, smoothing {:.6g} m; enclosed volume within {:.3g} of the "
                "liquid's on every frame", scale.voxel_size, scale.smoothing, out.surface_volume_error());
  }

  void run() {
    const auto& entry = choose_runner(scene_);
    log_.info("runner: {}: {}", entry.name, entry.summary);
    if (!quiet()) fmt::print("{}: {}\n", entry.name, entry.summary);
    auto sim = create_simulation(entry);
    Output out(opt_.out_dir, scene_["export"]);
    Stopwatch wall;
    sim->setup(scene_, time_steps_, log_);
    log_.info("setup done in {:.3f} s", wall.seconds());

    std::vector<std::string> header = {"step", "time", "dt"};
    for (const auto& p : sim->phases()) header.push_back("t_" + p);
    header.push_back("t_output");
    for (const auto& c : sim->columns()) header.push_back(c);
    const auto& probes = scene_["probes"];
    std::vector<std::string> probes_header;
    if (!probes.empty()) {
      probes_header = {"time"};
      for (const auto& p : probes)
        for (const auto& c : probe_columns(p)) probes_header.push_back(c);
    }
    if (resume_) {
      resume_run(*sim, out, header, probes_header, entry.name, wall);
      return;
    }
    if (writes_) out.begin_stats(header);
    if (writes_ && !probes.empty()) out.begin_probes(probes_header);

    check_finite(*sim, 0, 0.0);
    check_probes_answer(*sim);
    std::vector<double> probe_values = probe_row(*sim, 0, 0.0);
    StepReport setup;
    if (!sim->time_dependent()) {
      setup = sim->setup_report();
      check_row_finite(header, stats_row(setup, 0, 0.0, 0.0), 0, 0.0);
    }
    // A static runner's load steps: one probes row per step, the load factor as its time.
    std::vector<std::vector<double>> static_rows;
    const std::vector<double> factors = sim->time_dependent() ? std::vector<double>{} : sim->load_factors();
    if (!probes.empty() && !factors.empty()) {
      for (std::size_t k = 0; k < factors.size(); ++k) {
        sim->select_load_step(static_cast<int>(k));
        static_rows.push_back(probe_row(*sim, static_cast<long>(k), factors[k]));
      }
      sim->select_load_step(static_cast<int>(factors.size()) - 1);
    }
    Stopwatch io;
    write_frame(*sim, out, 0, 0.0);
    if (writes_ && !probes.empty() && static_rows.empty()) out.probes_row(probe_values);
    for (const auto& row : static_rows)
      if (writes_) out.probes_row(row);
    double t_output = io.seconds();
    if (!sim->time_dependent()) {
      if (writes_) out.stats_row(stats_row(setup, 0, 0.0, t_output));
      log_output_total(out);
      log_.info("done: frame 0 written in {:.3f} s (total {:.3f} s)", t_output, wall.seconds());
      return;
    }

    step_loop(*sim, out, header, entry.name, wall, 0.0, 0, 0);
  }

 private:
  /// `run --resume`: the set-up is done; the runner's state, the time loop's and the output's are
  /// overwritten with the checkpoint's, and the loop goes on from there.
  void resume_run(Simulation& sim, Output& out, const std::vector<std::string>& header,
                  const std::vector<std::string>& probes_header, const std::string& runner, const Stopwatch& wall) {
    LoadedCheckpoint& c = *resume_;
    Stopwatch clock;
    try {
      BinaryReader in = c.runner_state();
      sim.read_checkpoint(in);
      if (in.left() != 0) in.fail("runner state with trailing bytes");
    } catch (const BinaryReadError& e) {
      throw InputError(std::string("--resume: ") + e.what());
    }
    std::string().swap(c.bytes);
    out.resume(c.driver.output, header, probes_header);
    frames_written_ = c.driver.frames_written;
    for (auto i : c.driver.warned) warned_.insert(static_cast<std::size_t>(i));
    last_checkpoint_frame_ = c.driver.frame;
    log_.info("resumed from {} (frame {}, t = {:.6g} s, step {}) in {:.3f} s", c.file.string(), c.driver.frame,
              c.driver.time, c.driver.step, clock.seconds());
    if (!opt_.quiet) fmt::print("resumed from {} (frame {}, t = {:.6g} s)\n", c.file.string(), c.driver.frame, c.driver.time);
    step_loop(sim, out, header, runner, wall, c.driver.time, c.driver.step, c.driver.frame);
  }

  /// Writes the checkpoint of frame `frame` (export.checkpoint_every; checkpoint.hpp) and logs
  /// its size and write time.
  void checkpoint(const Simulation& sim, const Output& out, const std::string& runner, double t, long step, int frame) {
    Stopwatch clock;
    DriverState state{t, step, frame, frames_written_, out.state(), {}};
    for (auto i : warned_) state.warned.push_back(i);
    std::uintmax_t bytes = 0;
    const fs::path path = write_checkpoint(opt_.out_dir, scene_hash_, runner, state, sim, bytes);
    last_checkpoint_frame_ = frame;
    log_.info("checkpoint: frame {} (t = {:.6g} s, step {}): {} bytes written in {:.3f} s to {}", frame, t, step, bytes,
              clock.seconds(), path.string());
  }

  /// The time loop from (t, step, frame) to the end time.
  void step_loop(Simulation& sim_ref, Output& out, const std::vector<std::string>& header, const std::string& runner,
                 const Stopwatch& wall, double t, long step, int frame) {
    Simulation* sim = &sim_ref;
    const auto& probes = scene_["probes"];
    std::vector<double> probe_values;
    Stopwatch io;
    double t_output = 0;
    const double end = time_steps_.end_time;
    const double frame_dt = time_steps_.frame_interval();
    const double eps = 1e-12 * std::max(end, frame_dt);
    const long max_steps = time_steps_.max_steps;
    Progress progress(end, !quiet());
    progress.start(t, wall.seconds());  // the ETA leaves out set-up and frame 0
    try {
      while (t < end - eps) {
        const double next_frame = (frame + 1) * frame_dt;
        const double h_max = sim->max_dt(time_steps_);
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
        if (step >= max_steps)
          throw InputError(fmt::format("step {} (t = {:.6g} s of {:.6g} s): the run reached /simulation/max_steps = {} "
                                       "before its end time (the step follows the CFL condition: {:.3g} s); raise "
                                       "/simulation/max_steps, or shorten /simulation/end_time. Frames written so far "
                                       "are intact.", step, t, end, max_steps, h_max));
        StepReport r = sim->step(h);
        t = lands && r.dt == h ? target : t + r.dt;
        ++step;
        check_finite(*sim, step, t);
        check_physics(*sim, step, t);
        // Every number of the step's stats.csv and probes.csv rows is checked before anything of
        // the step (frame, probes row, stats row) is written.
        check_row_finite(header, stats_row(r, step, t, 0.0), step, t);
        probe_values = probe_row(*sim, step, t);
        io.restart();
        const bool at_frame = t >= next_frame - eps;
        if (at_frame) write_frame(*sim, out, ++frame, t);
        if (writes_ && !probes.empty()) out.probes_row(probe_values);
        t_output = io.seconds();
        if (writes_) out.stats_row(stats_row(r, step, t, t_output));
        // A checkpoint every checkpoint_every frames, and at the end when it lands on a frame (a
        // later --resume with a longer end time then goes on from there).
        const bool last = !(t < end - eps);
        if (at_frame && checkpoint_every_ > 0 && frame != last_checkpoint_frame_ &&
            (frame % checkpoint_every_ == 0 || last))
          checkpoint(*sim, out, runner, t, step, frame);
        progress.update(t, step, wall.seconds());
      }
    } catch (...) {
      progress.interrupt();
      throw;
    }
    progress.finish(t, step, wall.seconds());
    log_output_total(out);
    log_.info("done: {} steps, {} frames, simulated {:.6g} s in {:.3f} s of wall time", step, frame + 1,
              t, wall.seconds());
  }

  void check_finite(const Simulation& sim, long step, double t) {
    const std::string bad = sim.non_finite();
    if (bad.empty()) return;
    throw RunError(fmt::format(
        "step {} (t = {:.6g} s): non-finite value in {}: the simulation diverged. Nothing of this "
        "step was written; earlier frames are intact. Try a smaller time step (simulation.dt or "
        "simulation.cfl) or check the material parameters.",
        step, t, bad));
  }

  /// The physics watchdog of the runner (Simulation::unphysical), with the step and time.
  void check_physics(const Simulation& sim, long step, double t) {
    const std::string what = sim.unphysical();
    if (what.empty()) return;
    throw RunError(fmt::format("step {} (t = {:.6g} s): {}. Nothing of this step was written; earlier frames are "
                               "intact.", step, t, what));
  }

  /// The stats.csv row of a step: step, time, dt, the phase timings, t_output, the model's columns.
  static std::vector<double> stats_row(const StepReport& r, long step, double t, double t_output) {
    std::vector<double> row = {double(step), t, r.dt};
    row.insert(row.end(), r.phase_seconds.begin(), r.phase_seconds.end());
    row.push_back(t_output);
    row.insert(row.end(), r.values.begin(), r.values.end());
    return row;
  }

  /// A stats.csv value that is not finite (e.g. an energy that overflowed while the state is still
  /// finite, a time step that overflowed) stops the run before anything of the step is written.
  void check_row_finite(const std::vector<std::string>& names, const std::vector<double>& values, long step, double t) {
    for (std::size_t k = 0; k < values.size(); ++k)
      if (!std::isfinite(values[k]))
        throw RunError(fmt::format("step {} (t = {:.6g} s): the statistic {} is {}: the simulation diverged. Nothing "
                                   "of this step was written; earlier frames are intact. Try a smaller time step "
                                   "(simulation.dt or simulation.cfl) or check the loads and material parameters.",
                                   step, t, k < names.size() ? names[k] : std::to_string(k), values[k]));
  }

  /// Every probe of the scene is answered by this runner (preflight checks the kinds; this
  /// catches a runner that declares a kind it cannot give for this scene).
  void check_probes_answer(const Simulation& sim) {
    const auto& probes = scene_["probes"];
    for (std::size_t i = 0; i < probes.size(); ++i)
      if (sim.probe(probes[i]).size() != probe_columns(probes[i]).size())
        throw InputError(fmt::format("/probes/{}/kind: the runner of this scene has no probe \"{}\" here",
                                     i, probes[i]["kind"].get<std::string>()));
  }

  /// The probes.csv row at time t (empty if the scene has no probes). A probe value that is
  /// infinite, or NaN from any probe but a fluid_point (whose NaN means "outside the fluid" and is
  /// written as an empty cell), stops the run before anything of the step is written.
  std::vector<double> probe_row(const Simulation& sim, long step, double t) {
    const auto& probes = scene_["probes"];
    if (probes.empty()) return {};
    std::vector<double> row = {t};
    for (std::size_t i = 0; i < probes.size(); ++i) {
      auto values = sim.probe(probes[i]);
      const bool may_be_empty = probes[i]["kind"] == "fluid_point";
      for (double v : values)
        if (std::isinf(v) || (std::isnan(v) && !may_be_empty))
          throw RunError(fmt::format("step {} (t = {:.6g} s): probe /probes/{} ('{}') is {}: the simulation diverged. "
                                     "Nothing of this step was written; earlier frames are intact.",
                                     step, t, i, probes[i]["name"].get<std::string>(), v));
      if (std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); }) && warned_.insert(i).second)
        log_.warn("t = {:.6g} s: probe /probes/{} ('{}') has no value (outside the fluid?); its cells are left empty "
                  "while it has none", t, i, probes[i]["name"].get<std::string>());
      row.insert(row.end(), values.begin(), values.end());
    }
    return row;
  }

  /// No progress line: --quiet, or a process other than the first of an MPI run.
  bool quiet() const { return opt_.quiet || !writes_; }

  const RunOptions& opt_;
  /// Only the first MPI process writes the output folder and prints (the others hold the same
  /// state: parallel/mpi_session.hpp).
  const bool writes_ = parallel::rank() == 0;
  scene::Scene scene_;
  /// The one store of the time step above the library: dt or cfl, frame rate, end time, step limits.
  const scene::TimeStepPolicy time_steps_;
  spdlog::logger& log_;
  std::set<std::size_t> warned_;
  int frames_written_ = 0;
  LoadedCheckpoint* resume_ = nullptr;  ///< its file's bytes are released once read
  int checkpoint_every_ = 0;      ///< export.checkpoint_every (0: none)
  int last_checkpoint_frame_ = -1;
  std::uint64_t scene_hash_ = 0;  ///< checkpoint_scene_hash of the resolved scene
};

/// A process other than the first of an MPI run: the same set-up and steps as the first (the
/// distributed solves need every process), nothing written and nothing logged but errors.
void run_on_other_process(const RunOptions& opt, scene::Scene scene, const scene::TimeStepPolicy& time_steps) {
  if (opt.resume) throw InputError("--resume: continue a run on one process (without mpirun); its checkpoints are the same");
  const int threads = scene["simulation"].at("threads").get<int>();
  const int used = threads > 0 ? threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, used);
  parallel::set_library_threads(used);
  auto log = std::make_shared<spdlog::logger>("run", std::make_shared<spdlog::sinks::null_sink_mt>());
  Driver(opt, std::move(scene), time_steps, *log, nullptr).run();
}

}  // namespace

void run_scene(const RunOptions& opt) {
  scene::Scene scene = load_with_overrides(opt);
  if (parallel::rank() == 0) {  // the paths the run writes, before any work (output.hpp)
    std::vector<std::string> objects;
    for (const auto& s : scene["solids"]) objects.push_back(s.at("name").get<std::string>());
    if (scene["fluid"].at("type") != "none") objects.insert(objects.end(), {"fluid", "liquid"});
    if (scene.json.contains("mpm")) objects.insert(objects.end(), {"particles", "membrane"});
    check_output_folder(opt.out_dir, objects);
  }
  PreflightOptions checks;
  checks.max_tets = opt.max_tets;
  checks.processes = parallel::num_processes();
  const PreflightReport report = preflight(scene, checks);
  const scene::TimeStepPolicy time_steps = scene::read_time_step_policy(scene.json);  // --end-time applied
  if (parallel::rank() > 0) {
    run_on_other_process(opt, std::move(scene), time_steps);
    return;
  }
  if (opt.resume && parallel::num_processes() > 1)
    throw InputError("--resume: continue a run on one process (without mpirun); its checkpoints are the same");
  std::error_code ec;
  fs::create_directories(opt.out_dir, ec);
  if (ec || !fs::is_directory(opt.out_dir))
    throw InputError(fmt::format("cannot create the output folder {}: {}", opt.out_dir.string(),
                                 ec ? ec.message() : "not a folder"));
  const bool reused = fs::exists(opt.out_dir / "run.log");
  // --resume: the checkpoint is read (and refused with exit 2) before anything in the folder changes.
  std::optional<LoadedCheckpoint> resume;
  if (opt.resume) {
    const RunnerEntry& entry = choose_runner(scene);
    if (!entry.checkpoints || !entry.checkpoints(scene))
      throw InputError(fmt::format("--resume: the {} runner (which runs this scene) does not write checkpoints; the "
                                   "coupled, fluid, solid (dynamic) and mpm runners do", entry.name));
    resume = read_latest_checkpoint(opt.out_dir, checkpoint_scene_hash(scene.json), entry.name);
    if (!(resume->driver.time < time_steps.end_time))
      throw InputError(fmt::format("--resume: {} is at t = {:.6g} s, not before /simulation/end_time = {:.6g} s: "
                                   "nothing to continue (give a later --end-time)", resume->file.string(),
                                   resume->driver.time, time_steps.end_time));
  }
  std::shared_ptr<spdlog::logger> log;
  try {
    log = make_logger(opt.out_dir, !resume);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("cannot write run.log in the output folder {}: {}", opt.out_dir.string(), e.what()));
  }
  log->info("tetfsi {}", TETFSI_VERSION);
  if (!opt.command_line.empty()) log->info("command: {}", opt.command_line);
  log->info("scene: {}", fs::absolute(opt.scene_file).string());
  const OutputCleanup cleaned = clean_output_folder(opt.out_dir, reused, resume ? resume->driver.frame : -1);
  if (resume)
    log->info("resuming the run of {} from {}: {} frame file(s) written after it removed", opt.out_dir.string(),
              resume->file.string(), cleaned.earlier_run_files);
  else if (reused)
    log->warn("{} holds an earlier run: its frames, .pvd, CSV and checkpoint files ({} file(s)) were removed, other "
              "files are kept", opt.out_dir.string(), cleaned.earlier_run_files);
  if (cleaned.temporary_files > 0)
    log->info("removed {} orphan temporary file(s) of an interrupted run", cleaned.temporary_files);
  for (const auto& w : report.warnings) log->warn("{}", w);
  log->info("checks: runner {}, about {:.3g} tets (limit {:.3g}), at least {:.3g} steps (limit {}), {:.3g} frames, "
            "about {:.3g} GB of output", report.runner, report.tets, report.max_tets, report.steps,
            time_steps.max_steps, report.frames, report.output_bytes / 1e9);
  const int threads = scene["simulation"].at("threads").get<int>();
  const int used = threads > 0 ? threads : tbb::info::default_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, used);
  parallel::set_library_threads(used);
  log->info("threads: {}", used);
  if (parallel::num_processes() > 1)
    log->info("{} MPI processes: each runs the whole step with {} thread(s); the pressure and coupled solves run on "
              "PETSc with the rows spread over them; this one (rank 0) writes the output", parallel::num_processes(), used);
  const std::string resolved = scene.json.dump(2);
  log->info("resolved scene (defaults filled in; FNV-1a hash {:016x}; checkpoints' scene hash {:016x}):\n{}",
            fnv1a(resolved), checkpoint_scene_hash(scene.json), resolved);
  try {
    Driver(opt, std::move(scene), time_steps, *log, resume ? &*resume : nullptr).run();
  } catch (const std::exception& e) {
    log->sinks().back()->set_level(spdlog::level::off);  // main prints it on the console
    log->error("{}", e.what());
    log->flush();
    throw;
  }
  spdlog::drop("run");
}

}  // namespace tetfsi::run
