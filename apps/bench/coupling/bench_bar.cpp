// Benchmark of Chentanez et al. 2006, Fig. 6 / Table 1 (issue 6): wall time per simulated second of
// the bar between opposed jets (data/scenes/bar_compare.json), simultaneous coupling against time
// splitting, each at its largest stable step. For each scheme h is halved from 1/15 s until a run
// of `end_time` simulated seconds completes and stays bounded (max displacement of the bar centre below a
// tenth of the near-solid cell); its step time (advect + solid assembly + interface + solve, from
// stats.csv, meshing and output excluded) divided by the simulated time is the row's wall time.
// Rows for both schemes, then the ratio. The paper measured 2.9x in favour of simultaneous.
//
// Two bar densities: 250 kg/m³ (the committed scene; added mass m_a ≈ 0.47 kg against
// m_s = 0.19 kg, splitting has no stable step) and 700 kg/m³ (m_s = 0.53 kg > m_a: both stable).
//
// Usage: bench_bar [end_time_s] [scene]   (defaults: 2, data/scenes/bar_compare.json)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <unistd.h>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/bench/bench_support.hpp"
#include "apps/run/driver.hpp"

using namespace tetfsi;
namespace fs = std::filesystem;

namespace {

/// Column `name` of a CSV file with a header row, as numbers (empty if the column is missing).
std::vector<double> csv_column(const fs::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line, cell;
  std::getline(in, line);
  int col = -1, c = 0;
  std::stringstream header(line);
  while (std::getline(header, cell, ',')) {
    if (cell == name) col = c;
    ++c;
  }
  std::vector<double> out;
  while (col >= 0 && std::getline(in, line)) {
    std::stringstream ss(line);
    for (int k = 0; std::getline(ss, cell, ','); ++k)
      if (k == col) out.push_back(std::stod(cell));
  }
  return out;
}

struct Attempt {
  double h = 0;
  bool stable = false;
  std::string verdict;        ///< "bounded, max |u| ..." or the failure
  double step_seconds = 0;    ///< sum of the step phases [s]
};

Attempt run_once(const nlohmann::json& base, const fs::path& dir, const std::string& scheme, double h,
                 double density, double end_time, double bound) {
  nlohmann::json scene = base;
  scene["coupling"]["scheme"] = scheme;
  scene["simulation"]["dt"] = h;
  scene["simulation"]["end_time"] = end_time;
  scene["simulation"]["frame_rate"] = 1.0 / end_time;  // frames at 0 and the end only
  scene["solids"][0]["material"]["density"] = density;
  scene["export"] = {{"vtu", false}, {"surfaces", "none"}};
  const fs::path file = dir / "bar.json", out = dir / "out";
  fs::remove_all(out);
  std::ofstream(file) << scene.dump(2);
  run::RunOptions options;
  options.scene_file = file;
  options.out_dir = out;
  options.quiet = true;
  Attempt a;
  a.h = h;
  try {
    run::run_scene(options);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    // "coupled step at t = ... s (scheme coupling): cause"; a scene error would show as well.
    a.verdict = "failed: " + what.substr(0, 160);
    return a;
  }
  for (const char* phase : {"t_advect", "t_solid_assemble", "t_interface", "t_solve"})
    for (double t : csv_column(out / "stats.csv", phase)) a.step_seconds += t;
  double max_u = 0;
  for (const char* c : {"centre_x", "centre_y", "centre_z"})
    for (double u : csv_column(out / "probes.csv", c)) max_u = std::max(max_u, std::abs(u));
  a.stable = max_u < bound;
  a.verdict = fmt::format("{}, max displacement {:.2e} m", a.stable ? "bounded" : "grew past a tenth of a cell", max_u);
  return a;
}

/// Halves h from 1/15 s until stable (at most 7 halvings, to 1/1920 s); prints one row.
std::optional<Attempt> largest_stable(const nlohmann::json& base, const fs::path& dir, const std::string& scheme,
                                      double density, double end_time, double bound) {
  std::string tried;
  for (int k = 0; k <= 7; ++k) {
    const double h = 1.0 / (15 << k);
    const Attempt a = run_once(base, dir, scheme, h, density, end_time, bound);
    std::fprintf(stderr, "  %s rho_s %.0f h = 1/%d: %s\n", scheme.c_str(), density, 15 << k, a.verdict.c_str());
    if (a.stable) {
      bench::print_row(fmt::format("bar, {} (rho_s {:.0f})", scheme, density),
                       fmt::format("h = 1/{} s (largest stable), {} s simulated", 15 << k, end_time),
                       a.verdict + (tried.empty() ? "" : "; larger steps diverged"), a.step_seconds / end_time);
      return a;
    }
    tried += fmt::format(" 1/{}", 15 << k);
  }
  bench::print_row(fmt::format("bar, {} (rho_s {:.0f})", scheme, density), "no stable step down to 1/1920 s",
                   "diverged at h =" + tried, std::numeric_limits<double>::quiet_NaN());
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  const double end_time = argc > 1 ? std::atof(argv[1]) : 2.0;
  const fs::path scene_file =
      argc > 2 ? fs::path(argv[2]) : fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes" / "bar_compare.json";
  std::ifstream in(scene_file);
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", scene_file.c_str());
    return 2;
  }
  const nlohmann::json base = nlohmann::json::parse(in);
  const double bound = 0.1 * base["mesh"]["edge_length_near_solids"].get<double>();
  const fs::path dir = fs::temp_directory_path() / fmt::format("tetfsi_bench_bar_{}", static_cast<long>(getpid()));
  fs::create_directories(dir);

  bench::print_header();
  for (double density : {250.0, 700.0}) {
    const auto sim = largest_stable(base, dir, "simultaneous", density, end_time, bound);
    const auto split = largest_stable(base, dir, "time_splitting", density, end_time, bound);
    if (sim && split)
      bench::print_row(fmt::format("bar, splitting / simultaneous (rho_s {:.0f})", density), "each at its largest stable h",
                       fmt::format("ratio {:.2f} (paper 2.9)", split->step_seconds / sim->step_seconds), 0.0);
    else if (sim)
      bench::print_row(fmt::format("bar, splitting / simultaneous (rho_s {:.0f})", density), "each at its largest stable h",
                       "splitting has no stable step: ratio unbounded", 0.0);
  }
  fs::remove_all(dir);
  return 0;
}
