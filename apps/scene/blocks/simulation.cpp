#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {

Field simulation() {
  return Field::object("simulation", "Time stepping and global settings.", {
      Field::number("end_time", "s", "Simulated time at which the run stops.").req().greater(0),
      Field::number("dt", "s", "Time step. Steps land exactly on frame times: where a full step would leave less than "
                    "half a step before a frame, the rest is taken in two equal steps. If absent, the "
                    "step follows from `cfl`.").greater(0),
      Field::number("cfl", "", "Courant number used to choose the step when `dt` is absent.")
          .greater(0).def(0.5),
      Field::number("frame_rate", "1/s", "Output frames per simulated second.").greater(0).def(30),
      Field::vector("gravity", 3, "m/s^2", "Gravitational acceleration.").def({0, -9.81, 0}),
      Field::integer("threads", "Worker threads; 0 uses every core. `--threads` overrides it.")
          .at_least(0).def(0),
  });
}

}  // namespace tetfsi::scene::blocks
