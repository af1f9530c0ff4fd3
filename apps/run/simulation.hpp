#pragma once
/// @file simulation.hpp
/// The interface every model's runner implements, and the registry that picks one for a scene.
/// See apps/run/README.md for how to add a runner.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/logger.h>

#include "apps/run/output.hpp"
#include "apps/scene/scene.hpp"
#include "apps/scene/time_step_policy.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::run {

/// What one call of Simulation::step() did.
struct StepReport {
  double dt = 0;                     ///< time advanced h [s] (the stats.csv column dt)
  std::vector<double> phase_seconds;  ///< wall time of each phase, in the order of phases()
  std::vector<double> values;         ///< one value per columns() (counts and model statistics)
};

/// A model runner: built from the resolved scene, advanced step by step by the driver.
class Simulation {
 public:
  virtual ~Simulation() = default;

  /// Builds the model. `time_steps` is the driver's policy (read once from /simulation): the
  /// runner takes what its models need from it (max_step_halvings, a step cap) and never reads
  /// the time keys of the scene again. Throw InputError for problems with the scene or its files.
  virtual void setup(const scene::Scene& scene, const scene::TimeStepPolicy& time_steps, spdlog::logger& log) = 0;
  /// False for runners that only prepare and export (no time loop): the driver writes frame 0
  /// and one stats row, then stops.
  virtual bool time_dependent() const { return true; }
  /// Names of the timed phases of a step ("remesh", "solve", ...): stats.csv columns t_<name> [s].
  virtual std::vector<std::string> phases() const = 0;
  /// Model-specific stats.csv columns (counts, iterations, energies), declared up front.
  virtual std::vector<std::string> columns() const = 0;
  /// Largest step allowed now under the driver's policy [s]: its dt, the CFL step of the state
  /// (fluid/stable_step.hpp), or one frame interval.
  virtual double max_dt(const scene::TimeStepPolicy& time_steps) const = 0;
  /// Advances the state by `h` [s] (the driver may shorten steps to land on frame times).
  virtual StepReport step(double h) = 0;
  /// Reports the first non-finite value of the state ("solid 'ball' position of vertex 12"), or
  /// "" if the state is finite. Called after each step, before anything is written.
  virtual std::string non_finite() const = 0;
  /// The physics watchdog (/simulation/watchdog): "" if the state is physical, else a diagnosis
  /// naming the object and the key to change (inverted tets of a deforming solid, energy from
  /// nowhere). Called after each step, after non_finite(), before anything is written.
  virtual std::string unphysical() const { return ""; }
  /// Writes the current state as frame `frame` at time `time`.
  virtual void write_frame(Output& out, int frame, double time) = 0;
  /// Values of one probe (resolved JSON of /probes/i); empty if this model does not support it.
  virtual std::vector<double> probe(const scene::Json& probe) const { return {}; }
  /// A runner that is not time dependent and solves in load steps (static analysis): the load
  /// factor of each stored state (of its first solid), 0 (the rest state) first; empty otherwise.
  /// The driver then writes one probes.csv row per entry, its time column the load factor.
  virtual std::vector<double> load_factors() const { return {}; }
  /// Makes probe() answer for load step k (index into load_factors(); every solid shows its state
  /// at that load factor); the last one is selected after setup.
  virtual void select_load_step(int /*k*/) {}
  /// Report for the first stats row of a runner that is not time dependent (setup statistics).
  virtual StepReport setup_report() const { return {}; }

  /// Checkpoints (checkpoint.hpp), for runners whose RunnerEntry::checkpoints accepts the scene:
  /// writes everything step() changes and later steps read (state, warm starts, lagged solver
  /// blocks, cached operators, watchdog baselines), so that read_checkpoint() after setup() of
  /// the same scene makes the following steps bit for bit those of the run that wrote it.
  /// read_checkpoint throws BinaryReadError on a truncated or mismatching state.
  virtual void write_checkpoint(BinaryWriter& /*out*/) const {}
  virtual void read_checkpoint(BinaryReader& /*in*/) {}
};

/// One registered runner.
struct RunnerEntry {
  std::string name;
  std::string summary;                                  ///< for run.log
  std::function<bool(const scene::Scene&)> accepts;     ///< can it run this scene?
  /// Probe kinds (/probes/i/kind) its probe() answers; empty: every kind the scene checks allow.
  std::vector<std::string> probe_kinds = {};
  /// Whether it writes checkpoints for this scene (Simulation::write_checkpoint); empty: never.
  std::function<bool(const scene::Scene&)> checkpoints = {};
};

/// Every runner, most specific first; the first that accepts a scene runs it (runners.cpp).
const std::vector<RunnerEntry>& runners();
/// The runner for `scene`.
const RunnerEntry& choose_runner(const scene::Scene& scene);
/// A new simulation of `runner` (runner_factories.cpp; the registry itself links no runner).
std::unique_ptr<Simulation> create_simulation(const RunnerEntry& runner);

/// Scene predicates of the runner choice (runners.cpp): a solid that deforms (motion "none") as a
/// tet_fem solid, as a hex8 solid, or as `model`.
bool is_deformable_tet(const scene::Json& solid);
bool is_hex(const scene::Json& solid);
bool deforms_as(const scene::Json& solid, const char* model);

}  // namespace tetfsi::run
