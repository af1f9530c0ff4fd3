#pragma once
/// @file standing_wave.hpp
/// The first sloshing mode of a rectangular tank, shared by the free-surface test and bench_fluid.
///
/// Tank [0, L] x [0, W] x [0, 1.5 H] with still depth H, walls all round, a free surface
/// eta(x, 0) = a cos(k x) with k = pi / L and the liquid at rest. Linear theory (Lamb 1932,
/// "Hydrodynamics", sec. 227): a standing wave eta = a cos(k x) cos(omega t) with
///   omega^2 = g k tanh(k H).
/// Measured: the mode amplitude A(t) = sum_v (z_v - H) cos(k x_v) / sum_v cos^2(k x_v) over the
/// vertices of the zero set; the period from its zero crossings (linear interpolation in time),
/// the decay from successive extrema |A|.
#include <Eigen/Core>
#include <cmath>
#include <random>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "fluid/liquid/level_set.hpp"
#include "mesh/structured_box.hpp"

namespace tetfsi::bench {

struct StandingWaveResult {
  int tets = 0;
  double period = 0.0;             ///< measured [s]
  double period_theory = 0.0;      ///< 2 pi / omega [s]
  double decay_per_period = 0.0;   ///< 1 - |A(t + T)| / |A(t)| from the extrema [-]
  double max_volume_drift = 0.0;   ///< max |volume_drift| per step [-]
  double max_divergence = 0.0;     ///< max weak divergence after projection [1/s]
  int steps = 0;
  std::vector<double> time, amplitude;  ///< A(t) [s, m]
};

/// Runs the standing wave on an n x 2 x (3n/4) box of Kuhn tets (interior vertices jittered by
/// up to 0.1 of a cell), n cells along L = 1 m, H = 0.5 m, a = 0.01 H, for `periods` periods at
/// `steps_per_period` steps per period.
inline StandingWaveResult standing_wave(int n, double periods = 2.25, int steps_per_period = 40) {
  const double L = 1.0, H = 0.5, a = 0.01 * H, g = 9.81, pi = std::acos(-1.0), k = pi / L;
  const double dx = L / n, omega = std::sqrt(g * k * std::tanh(k * H));
  const int nz = (3 * n) / 4;
  const Eigen::Vector3d lo(0, 0, 0), hi(L, 2 * dx, nz * dx);
  mesh::TetMesh m = mesh::structured_box(lo, hi, n, 2, nz);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> jitter(-0.1 * dx, 0.1 * dx);
  for (auto& x : m.vertices) {
    const bool boundary = ((x - lo).array().abs() < 1e-9).any() || ((x - hi).array().abs() < 1e-9).any();
    const Eigen::Vector3d off(jitter(rng), jitter(rng), jitter(rng));
    if (!boundary) x += off;
  }
  fluid::FluidParams params;
  params.density = 1000.0;
  params.gravity = Eigen::Vector3d(0, 0, -g);
  params.solver.tolerance = 1e-10;
  fluid::FluidSolver solver(params);
  solver.initialize(m);
  fluid::LiquidOptions liquid;
  liquid.band = 4 * dx;
  solver.set_liquid(fluid::sample_level_set(solver.mesh(),
                                            [&](const Eigen::Vector3d& x) { return x.z() - H - a * std::cos(k * x.x()); }),
                    liquid);
  auto amplitude = [&] {
    double num = 0, den = 0;
    for (const auto& x : fluid::zero_set(solver.mesh(), solver.level_set()).vertices) {
      num += (x.z() - H) * std::cos(k * x.x());
      den += std::cos(k * x.x()) * std::cos(k * x.x());
    }
    return num / den;
  };
  StandingWaveResult r;
  r.tets = solver.mesh().num_tets();
  r.period_theory = 2 * pi / omega;
  const double dt = r.period_theory / steps_per_period;
  r.steps = static_cast<int>(std::ceil(periods * steps_per_period));
  std::vector<double> time{0.0}, amp{amplitude()};
  for (int s = 1; s <= r.steps; ++s) {
    const fluid::StepReport rep = solver.step(m, {}, dt);
    r.max_volume_drift = std::max(r.max_volume_drift, std::abs(rep.volume_drift));
    r.max_divergence = std::max(r.max_divergence, rep.max_divergence);
    time.push_back(s * dt);
    amp.push_back(amplitude());
  }
  r.time = time;
  r.amplitude = amp;
  std::vector<double> crossings, extrema;
  double extreme = 0.0;
  for (size_t s = 1; s < amp.size(); ++s) {
    if (std::abs(amp[s]) > std::abs(extreme)) extreme = amp[s];
    if ((amp[s - 1] > 0) != (amp[s] > 0)) {
      crossings.push_back(time[s - 1] + (time[s] - time[s - 1]) * amp[s - 1] / (amp[s - 1] - amp[s]));
      if (crossings.size() > 1) extrema.push_back(std::abs(extreme));
      extreme = 0.0;
    }
  }
  if (crossings.size() >= 2)
    r.period = 2.0 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  // Extrema half a period apart: the decay over a period is 1 - (ratio of consecutive)^2.
  if (extrema.size() >= 2)
    r.decay_per_period = 1.0 - std::pow(extrema.back() / extrema.front(), 2.0 / (extrema.size() - 1));
  return r;
}

}  // namespace tetfsi::bench
