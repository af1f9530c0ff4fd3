// Squeeze film through the incompressible solve (issue: contact through the fluid): a stiff disc
// of radius R driven at constant speed V toward the floor of a closed tank of water
// (data/scenes/squeeze_film.json), through `tetfsi run`, its pressure force from the
// `fluid_force` probe. In a gap h ≪ R the radial plug flow u_r = V r / (2h) has two inviscid limits:
//  - p = 0 at the rim (the water leaves as a free jet): continuity and unsteady Bernoulli give
//    F_jet = 3 π ρ V² R⁴ / (16 h²);
//  - potential flow (the film's kinetic energy T = π ρ V² R⁴ / (16 h) stays in the fluid): the
//    added mass m_a = π ρ R⁴ / (8h) and Lagrange's equations at constant V give F = ½ V² |dm_a/dh|
//    = F_jet / 3.
// The Euler solve with its numerical dissipation at the rim must lie between the two over the
// decade 0.05 ≤ h/R ≤ 0.3, and grow about as h⁻².
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

TEST(SqueezeFilm, DiscDrivenAtAWallFeelsTheThinFilmForce) {
  TempDir dir("squeeze");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_command(std::string(TETFSI_BINARY) + " run " + TETFSI_SOURCE_DIR +
                                          "/data/scenes/squeeze_film.json --out " + out.string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv");
  const double rho = 1000, V = 0.1, R = 0.1, h0 = 0.05;
  std::vector<double> ratio, log_h, log_f;
  std::printf("   h/R   F [N]   F / F_jet\n");
  for (std::size_t r = 1; r < probes.rows.size(); ++r) {
    const double h = h0 - V * probes.at(r, "time");
    if (h < 0.05 * R - 1e-9 || h > 0.3 * R) continue;
    const double f = probes.at(r, "force_y"), f_jet = 3 * M_PI * rho * V * V * std::pow(R, 4) / (16 * h * h);
    ASSERT_GT(f, 0) << "the film pushes the disc back at h = " << h;
    ratio.push_back(f / f_jet);
    log_h.push_back(std::log(h));
    log_f.push_back(std::log(f));
    if (ratio.size() % 5 == 1) std::printf("  %.3f  %6.3f   %.3f\n", h / R, f, f / f_jet);
  }
  ASSERT_GE(ratio.size(), 40u);
  // Least-squares slope of log F against log h.
  const double n = static_cast<double>(ratio.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < ratio.size(); ++i) mx += log_h[i] / n, my += log_f[i] / n;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < ratio.size(); ++i) sxy += (log_h[i] - mx) * (log_f[i] - my), sxx += std::pow(log_h[i] - mx, 2);
  const double slope = sxy / sxx;
  std::vector<double> sorted = ratio;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const auto inside = std::count_if(ratio.begin(), ratio.end(), [](double q) { return q >= 0.3 && q <= 1.05; });
  std::printf("%zu samples: median F / F_jet %.3f, %ld within [0.3, 1.05], slope d log F / d log h %.3f\n",
              ratio.size(), median, static_cast<long>(inside), slope);
  EXPECT_GE(median, 1.0 / 3.0);
  EXPECT_LE(median, 1.0);
  EXPECT_GE(inside, static_cast<long>(0.9 * n));  // steps just after a remesh can stray
  EXPECT_LT(slope, -1.5);
  EXPECT_GT(slope, -2.2);
}
