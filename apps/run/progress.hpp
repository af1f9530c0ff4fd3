#pragma once
/// @file progress.hpp
/// The progress line of `tetfsi run`: rewritten in place on a terminal, plain lines every few
/// seconds otherwise (CI logs, files).
#include <cstdio>
#include <string>

namespace tetfsi::run {

/// Estimate of the wall time left: a running mean of the wall time per simulated second times the
/// simulated time left. The mean is over roughly the last tenth of the run (an exponential mean
/// whose weight per sample is the simulated time it covers over a tenth of end_time), and a plain
/// mean while that weight is below 1/n. Set-up and the first step (one-off solver costs) are not
/// in it.
class EtaEstimate {
 public:
  explicit EtaEstimate(double end_time) : end_(end_time) {}
  /// Adds the state after a step: simulated time t [s] reached at wall time `wall` [s].
  void add(double t, double wall);
  /// Wall time left [s], or a negative value before the first two samples.
  double seconds_left() const;

 private:
  double end_;
  double last_t_ = -1, last_wall_ = 0;  ///< the latest sample
  long samples_ = 0;
  double rate_ = -1;  ///< wall seconds per simulated second
};

class Progress {
 public:
  /// @param end_time simulated end time [s]; @param enabled false for --quiet
  /// Call start() when the stepping starts (after set-up and frame 0).
  Progress(double end_time, bool enabled);
  /// Marks the start of the time stepping at wall time `wall` [s] and simulated time t [s].
  void start(double t, double wall) { eta_.add(t, wall); }
  /// Reports simulated time `t` [s] after `step` steps and `wall` seconds of wall time.
  void update(double t, long step, double wall);
  /// Ends the in-place line (prints the final state).
  void finish(double t, long step, double wall);
  /// Ends an in-place line without a final state (before an error message).
  void interrupt();

 private:
  std::string line(double t, long step, double wall) const;
  double end_;
  bool enabled_, tty_;
  double last_print_ = -1e30;
  bool dirty_ = false;
  EtaEstimate eta_;
};

}  // namespace tetfsi::run
