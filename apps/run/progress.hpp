#pragma once
/// @file progress.hpp
/// The progress line of `tetfsi run`: rewritten in place on a terminal, plain lines every few
/// seconds otherwise (CI logs, files).
#include <cstdio>
#include <string>

namespace tetfsi::run {

class Progress {
 public:
  /// @param end_time simulated end time [s]; @param enabled false for --quiet
  Progress(double end_time, bool enabled);
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
};

}  // namespace tetfsi::run
