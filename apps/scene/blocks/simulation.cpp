#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "apps/scene/blocks/blocks.hpp"
#include "apps/scene/input_error.hpp"
#include "apps/scene/time_step_policy.hpp"

namespace tetfsi::scene {
namespace blocks {

Field simulation() {
  return Field::object("simulation", "Time stepping and global settings.", {
      Field::number("end_time", "s", "Simulated time at which the run stops.").req().greater(0),
      Field::number("dt", "s", "Time step. Steps land exactly on frame times: where a full step would leave less than "
                    "half a step before a frame, the rest is taken in two equal steps. If absent, the "
                    "step follows from `cfl`.").greater(0),
      Field::number("cfl", "", "Courant number used to choose the step when `dt` is absent.")
          .greater(0).def(0.5),
      Field::number("frame_rate", "1/s", "Output frames per simulated second.").greater(0).def(30),
      Field::vector("gravity", 3, "m/s^2", "Gravitational acceleration (or any uniform body acceleration). Each component is bounded by "
                    "1e7 m/s^2, about 1e6 g, the strongest ultracentrifuges: no liquid, gas or rubber of these "
                    "models is put under more (beyond it the first steps' velocities g dt leave any physical "
                    "range, and a CFL-chosen step shrinks as 1 / (g t)).")
          .at_least(-1e7).at_most(1e7).def({0, -9.81, 0}),
      Field::integer("threads", "Worker threads; 0 uses every core. `--threads` overrides it.")
          .at_least(0).at_most(1024).def(0),
      Field::integer("max_steps", "Largest number of steps the run may take; a scene whose end_time, dt or "
                     "frame_rate asks for more is refused before it starts, and a run whose CFL step makes it "
                     "take more stops (exit 2). Raise it for long runs.")
          .at_least(1).def(1000000),
      Field::integer("max_step_halvings",
                     "Coupled fluid-solid scenes: a step whose solid motion would invert or flatten fluid tets "
                     "(a solid moving fast, or closing in on a wall or another solid) is undone and taken as two "
                     "half steps, each halved again if needed, at most this many times (down to dt / 2^N); "
                     "after that the run stops (exit 1). Solid-only tet scenes: the same for a step that "
                     "inverts a solid tet or whose solve fails (a hard landing). 0: stop at once. stats.csv's "
                     "`substeps` counts the steps taken.")
          .at_least(0).at_most(20).def(6),
      Field::object("watchdog", "Stops a run that goes unphysical (exit 1, with the object, the step and the key "
                    "to change); non-finite values always stop it.", {
          Field::boolean("allow_inverted", "Keep running when tets of a deforming tet solid invert (volume <= 0); "
                         "by default the first inverted tet stops the run. (An inverted hex8 element always stops "
                         "it: it has no internal force.)").def(false),
          Field::number("max_energy_growth", "",
                        "Largest rise of the total energy above its start, as a fraction of the energy scale (the "
                        "largest kinetic + elastic energy so far, at least m |g| L summed over the solids of mass m "
                        "and size L), where every load is conservative so that a "
                        "rise is energy from nowhere: solid-only tet scenes (kinetic + elastic + gravitational + "
                        "springs), dynamic hex8 scenes (the same minus the work f.d of the dead loads) and coupled "
                        "fluid-solid scenes in a closed container (plus the fluid's kinetic and gravitational "
                        "energy, and rho V |g| h in the scale floor for a free-surface liquid of volume V on cells "
                        "of edge h; not watched with inflows, open faces, emitters or vorticity confinement, which "
                        "supply energy). Raise it to let such a run continue.")
              .greater(0).def(0.5)}),
  });
}

}  // namespace blocks

namespace {

/// /simulation/<key> as a finite number in [lo, hi] (`above_lo`: > lo); `integer`: a whole number.
double simulation_number(const Json& sim, const char* key, double lo, bool above_lo, double hi, bool integer) {
  const std::string where = fmt::format("/simulation/{}", key);
  if (!sim.contains(key)) throw InputError(where + ": missing");
  const Json& v = sim.at(key);
  if (!v.is_number()) throw InputError(fmt::format("{}: expected a number, got {}", where, v.dump()));
  const double x = v.get<double>();
  const bool in_range = std::isfinite(x) && (above_lo ? x > lo : x >= lo) && x <= hi;
  if (!in_range || (integer && std::floor(x) != x))
    throw InputError(fmt::format("{}: expected a finite {} {} {}{}, got {}", where, integer ? "integer" : "number",
                                 above_lo ? ">" : ">=", lo,
                                 hi < std::numeric_limits<double>::max() ? fmt::format(" and <= {}", hi) : "",
                                 v.dump()));
  return x;
}

}  // namespace

/// The reader of the block above (time_step_policy.hpp): its keys once, checked as the schema does.
TimeStepPolicy read_time_step_policy(const Json& scene) {
  if (!scene.contains("simulation") || !scene.at("simulation").is_object())
    throw InputError("/simulation: missing (it holds the end time)");
  const Json& sim = scene.at("simulation");
  constexpr double kAny = std::numeric_limits<double>::max();
  TimeStepPolicy p;
  if (sim.contains("dt")) p.dt = simulation_number(sim, "dt", 0, true, kAny, false);
  p.cfl = simulation_number(sim, "cfl", 0, true, kAny, false);
  p.frame_rate = simulation_number(sim, "frame_rate", 0, true, kAny, false);
  p.end_time = simulation_number(sim, "end_time", 0, true, kAny, false);
  p.max_steps = static_cast<long>(simulation_number(sim, "max_steps", 1, false, 2147483647.0, true));
  p.max_step_halvings = static_cast<int>(simulation_number(sim, "max_step_halvings", 0, false, 20, true));
  return p;
}

}  // namespace tetfsi::scene
