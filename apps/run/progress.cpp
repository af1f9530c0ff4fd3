#include "apps/run/progress.hpp"

#include <unistd.h>

#include <algorithm>

#include <fmt/format.h>

namespace tetfsi::run {

void EtaEstimate::add(double t, double wall) {
  // The first step carries one-off costs (solver set-up, first factorization): it only starts the
  // clock. Then the mean is plain (weight 1/n) until the exponential weight of a tenth of the run
  // is larger.
  if (last_t_ >= 0 && t > last_t_ && ++samples_ > 1) {
    const double rate = (wall - last_wall_) / (t - last_t_);
    const double weight = std::max(1.0 / (samples_ - 1), end_ > 0 ? std::min(1.0, (t - last_t_) / (0.1 * end_)) : 1.0);
    rate_ = rate_ < 0 ? rate : (1 - weight) * rate_ + weight * rate;
  }
  last_t_ = t;
  last_wall_ = wall;
}

double EtaEstimate::seconds_left() const { return rate_ < 0 ? -1.0 : rate_ * std::max(0.0, end_ - last_t_); }

Progress::Progress(double end_time, bool enabled)
    : end_(end_time), enabled_(enabled), tty_(::isatty(::fileno(stdout)) != 0), eta_(end_time) {}

std::string Progress::line(double t, long step, double wall) const {
  const double fraction = end_ > 0 ? t / end_ : 1.0;
  const double left = eta_.seconds_left();
  std::string eta = left >= 0 && fraction < 1 ? fmt::format("{:.1f} s", left) : "-";
  return fmt::format("t = {:.4g} / {:.4g} s ({:3.0f}%)  step {}  wall {:.1f} s  ETA {}", t, end_,
                     100 * fraction, step, wall, eta);
}

void Progress::update(double t, long step, double wall) {
  eta_.add(t, wall);
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
