/// @file preflight_limits.cpp
/// The resource limits of preflight.hpp (tets, voxels: shares of this machine's memory) and the
/// byte counts of its messages.
#include <unistd.h>

#include <cmath>

#include <fmt/format.h>

#include "apps/run/preflight.hpp"

namespace tetfsi::run {

namespace {
/// Physical memory of this machine [bytes] (8 GB if unknown).
double physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 8e9;
}
}  // namespace

std::string format_bytes(double bytes) {
  if (bytes < 1e6) return fmt::format("{:.3g} kB", bytes / 1e3);
  if (bytes < 1e9) return fmt::format("{:.3g} MB", bytes / 1e6);
  return fmt::format("{:.3g} GB", bytes / 1e9);
}

double default_max_tets() { return std::floor(0.5 * physical_memory() / kBytesPerTet); }

double default_max_voxels() { return std::floor(0.25 * physical_memory() / kBytesPerVoxel); }

double default_max_particles() { return std::floor(0.25 * physical_memory() / kBytesPerParticle); }

}  // namespace tetfsi::run
