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
#include <algorithm>
#include <cmath>
#include <functional>
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
  /// 1 - E(t + T) / E(t) of the wave's energy E = KE + PE - PE_flat (PE_flat: the same volume
  /// at rest, rho g V^2 / (2 L W)), from its means over the first and the last whole period [-]
  double energy_loss_per_period = 0.0;
  double max_volume_drift = 0.0;   ///< max |volume_drift| per step [-]
  double max_divergence = 0.0;     ///< max weak divergence after projection [1/s]
  int steps = 0;
  int particles = 0;               ///< particles at the end (0 without)
  double particle_seconds = 0.0;   ///< time in the particle phase, all steps [s]
  std::vector<double> time, amplitude, energy;  ///< A(t), E(t) [s, m, J]
};

/// The tank, the wave and the run.
struct StandingWaveSetup {
  double length = 1.0;      ///< L [m]
  double width = 0.0;       ///< W [m]; 0: two cells
  double depth = 0.5;       ///< still depth H [m]
  double amplitude = 0.005; ///< a [m]
  int cells = 32;           ///< cells along L (Kuhn cubes of 6 tets, tank height 1.5 H)
  double periods = 2.25;
  int steps_per_period = 40;
  fluid::AdvectionScheme advection = fluid::AdvectionScheme::kLinear;
  fluid::ParticleOptions particles;  ///< velocity on particles (none by default)
  bool level_set_bfecc = false;
  /// Called after every step with the solver (tests look at its state); may be empty.
  std::function<void(const fluid::FluidSolver&)> after_step;
};

/// Runs the standing wave of `setup` on an n x m x (3n H / 2 L) box of Kuhn tets (interior
/// vertices jittered by up to 0.1 of a cell), a surface eta = a cos(k x), k = pi / L, at rest.
inline StandingWaveResult standing_wave(const StandingWaveSetup& setup) {
  const double L = setup.length, H = setup.depth, a = setup.amplitude, g = 9.81, pi = std::acos(-1.0), k = pi / L;
  const int n = setup.cells;
  const double dx = L / n, omega = std::sqrt(g * k * std::tanh(k * H));
  const int ny = setup.width > 0 ? std::max(1, static_cast<int>(std::lround(setup.width / dx))) : 2;
  const double W = setup.width > 0 ? setup.width : 2 * dx;
  const int nz = static_cast<int>(std::floor(1.5 * H / dx + 1e-9));
  const Eigen::Vector3d lo(0, 0, 0), hi(L, W, nz * dx);
  mesh::TetMesh m = mesh::structured_box(lo, hi, n, ny, nz);
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
  params.advection = setup.advection;
  params.particles = setup.particles;
  fluid::FluidSolver solver(params);
  solver.initialize(m);
  fluid::LiquidOptions liquid;
  liquid.band = 4 * dx;
  liquid.bfecc = setup.level_set_bfecc;
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
  auto wave_energy = [&](fluid::StepReport rep) {
    solver.report_energies(rep);
    const double V = solver.liquid().total_volume();
    return rep.kinetic_energy + rep.gravity_potential - params.density * g * V * V / (2 * L * W);
  };
  StandingWaveResult r;
  r.tets = solver.mesh().num_tets();
  r.period_theory = 2 * pi / omega;
  const double dt = r.period_theory / setup.steps_per_period;
  r.steps = static_cast<int>(std::ceil(setup.periods * setup.steps_per_period));
  std::vector<double> time{0.0}, amp{amplitude()}, energy{wave_energy({})};
  for (int s = 1; s <= r.steps; ++s) {
    const fluid::StepReport rep = solver.step(m, {}, dt);
    r.max_volume_drift = std::max(r.max_volume_drift, std::abs(rep.volume_drift));
    r.max_divergence = std::max(r.max_divergence, rep.max_divergence);
    r.particle_seconds += rep.particle_seconds;
    r.particles = rep.num_particles;
    time.push_back(s * dt);
    amp.push_back(amplitude());
    energy.push_back(wave_energy(rep));
    if (setup.after_step) setup.after_step(solver);
  }
  r.time = time;
  r.amplitude = amp;
  r.energy = energy;
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
  // The wave's energy oscillates within a period at 2 omega by O(omega h) (the surface is moved by
  // the velocity before the step's forces, as in symplectic Euler), so it is compared period by
  // period: the mean of E over the steps of period k, E_k, and the loss per period
  // 1 - (E_{K-1} / E_0)^(1 / (K - 1)) over the K whole periods run.
  const int spp = setup.steps_per_period, whole = r.steps / spp;
  if (whole >= 2) {
    auto period_mean = [&](int k) {
      double sum = 0;
      for (int s = k * spp + 1; s <= (k + 1) * spp; ++s) sum += energy[s];
      return sum / spp;
    };
    r.energy_loss_per_period = 1.0 - std::pow(period_mean(whole - 1) / period_mean(0), 1.0 / (whole - 1));
  }
  return r;
}

/// The standing wave of the tests: L = 1 m, H = 0.5 m, a = 0.01 H, two cells wide, n cells along L,
/// `periods` periods at `steps_per_period` steps per period, the mesh advection.
inline StandingWaveResult standing_wave(int n, double periods = 2.25, int steps_per_period = 40) {
  StandingWaveSetup setup;
  setup.cells = n;
  setup.periods = periods;
  setup.steps_per_period = steps_per_period;
  return standing_wave(setup);
}

}  // namespace tetfsi::bench
