#include "apps/run/progress.hpp"

#include <unistd.h>

#include <fmt/format.h>

namespace tetfsi::run {

Progress::Progress(double end_time, bool enabled)
    : end_(end_time), enabled_(enabled), tty_(::isatty(::fileno(stdout)) != 0) {}

std::string Progress::line(double t, long step, double wall) const {
  const double fraction = end_ > 0 ? t / end_ : 1.0;
  std::string eta = fraction > 0 && fraction < 1 ? fmt::format("{:.1f} s", wall * (1 - fraction) / fraction) : "-";
  return fmt::format("t = {:.4g} / {:.4g} s ({:3.0f}%)  step {}  wall {:.1f} s  ETA {}", t, end_,
                     100 * fraction, step, wall, eta);
}

void Progress::update(double t, long step, double wall) {
  if (!enabled_) return;
  if (tty_) {
    if (wall - last_print_ < 0.1) return;
    fmt::print("\r{}\x1b[K", line(t, step, wall));
    std::fflush(stdout);
    dirty_ = true;
  } else {
    if (wall - last_print_ < 5.0) return;
    fmt::print("{}\n", line(t, step, wall));
    std::fflush(stdout);
  }
  last_print_ = wall;
}

void Progress::finish(double t, long step, double wall) {
  if (!enabled_) return;
  if (tty_) fmt::print("\r{}\x1b[K\n", line(t, step, wall));
  else fmt::print("{}\n", line(t, step, wall));
  std::fflush(stdout);
}

void Progress::interrupt() {
  if (enabled_ && tty_ && dirty_) fmt::print("\n");
  dirty_ = false;
  std::fflush(stdout);
}

}  // namespace tetfsi::run
