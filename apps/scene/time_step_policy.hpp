#pragma once
/// @file time_step_policy.hpp
/// The time stepping of a run, read once from the resolved scene's /simulation block. The keys,
/// defaults and ranges are the schema's (apps/scene/blocks/simulation.cpp, where
/// read_time_step_policy sits beside the block). The driver (apps/run/driver.cpp) owns the one
/// TimeStepPolicy of a run: it steps from 0 to end_time landing on every frame time
/// k / frame_rate, stops a run that needs more than max_steps steps, and hands the policy to the
/// runner (Simulation::setup and Simulation::max_dt, apps/run/simulation.hpp), which answers the
/// largest step allowed now (dt, or the CFL step of fluid/stable_step.hpp, or one frame) and
/// passes each step's length h on to its stepper.
#include <optional>

#include "apps/scene/schema.hpp"

namespace tetfsi::scene {

struct TimeStepPolicy {
  /// /simulation/dt: a fixed step h [s]. Absent: the fluid and coupled runners take the CFL step
  /// of `cfl`, the other runners one frame.
  std::optional<double> dt;
  double cfl = 0.5;           ///< /simulation/cfl: Courant number C of the CFL step (without dt)
  double frame_rate = 30;     ///< /simulation/frame_rate: output frames per simulated second [1/s]
  double end_time = 0;        ///< /simulation/end_time [s] (with `run --end-time` applied)
  long max_steps = 1000000;   ///< /simulation/max_steps: the most steps a run may take
  /// /simulation/max_step_halvings: how often a failed step may be halved (down to h / 2^N).
  int max_step_halvings = 6;

  /// The frame interval 1 / frame_rate [s], the longest step of any runner.
  double frame_interval() const { return 1.0 / frame_rate; }
  /// The step of a runner without a CFL rule [s]: dt, else one frame interval.
  double fixed_step() const { return dt ? *dt : frame_interval(); }
};

/// Reads /simulation of a resolved scene (defaults filled in, `run --end-time` applied).
/// @throws InputError naming the key (e.g. "/simulation/dt") for a value that is missing, not a
///         number, not finite or outside the schema's range
TimeStepPolicy read_time_step_policy(const Json& scene);

}  // namespace tetfsi::scene
