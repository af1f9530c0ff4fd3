#pragma once
/// @file bench_support.hpp
/// Shared pieces of the benchmarks: a wall clock, peak resident memory, and the one table
/// format every benchmark prints, so that their outputs add up to one speed-against-error report:
///
///   | case | resolution | error vs reference | wall time [s] | peak memory [MB] |
#include <fmt/core.h>

#include "support/stopwatch.hpp"
#include <string>

#include <sys/resource.h>

namespace tetfsi::bench {

using tetfsi::Stopwatch;  // seconds since construction (support/stopwatch.hpp)

/// Peak resident set size of this process so far [MB] (getrusage ru_maxrss, in KiB on Linux).
inline double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

/// Prints the table header (Markdown, so reports can paste it as is).
inline void print_header() {
  fmt::print("| case | resolution | error vs reference | wall time [s] | peak memory [MB] |\n");
  fmt::print("|---|---|---|---|---|\n");
}

/// Prints one row. `error` is free text such as "2.3e-3 rel. (tip deflection)".
inline void print_row(const std::string& name, const std::string& resolution, const std::string& error,
                      double wall_seconds) {
  fmt::print("| {} | {} | {} | {:.3f} | {:.1f} |\n", name, resolution, error, wall_seconds, peak_memory_mb());
  std::fflush(stdout);
}

}  // namespace tetfsi::bench
