#pragma once
/// @file stopwatch.hpp
/// The one wall-clock timer of the project (steady clock), for the per-phase timings of
/// stats.csv, the solver reports and the benchmarks.
#include <chrono>

namespace tetfsi {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  /// Seconds since construction or the last restart() / lap().
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }
  /// seconds(), then restart(): consecutive laps add up to the time since construction.
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace tetfsi
