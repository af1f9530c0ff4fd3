// bench_fluid: seconds per phase of a fluid step (advect, assemble, solve) at ~25k, 100k and 400k
// tets, and the validation errors of tests/fluid at finer resolutions.
//   bench_fluid [--max-tets N] [--sphere-only] [--scaling-only] [--standing-wave] [--liquid] [--sizes A,B,..]
//   bench_fluid --sloshing [--sizes 16,24,32,48] [--steps-per-period 40,80] [--periods 20]
//               [--schemes linear,apic,flip]   (the sloshing tank of sloshing_case, one row per run)
//   (max tets default 450000; --liquid: the free-surface step at about 25k, 100k and 400k tets;
//   --sizes: the resolutions of --standing-wave (cells per tank length, default 16,32,64) and of
//   --sphere-only (edge at the sphere [m], default 0.12,0.08,0.055), as scripts/report.py runs them)
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "apps/bench/bench_support.hpp"
#include "apps/bench/fluid/sphere_cases.hpp"
#include "apps/bench/fluid/standing_wave.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/liquid/level_set.hpp"
#include "mesh/structured_box.hpp"

namespace {

using namespace tetfsi;

mesh::TetMesh jittered(const mesh::TetMesh& base, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double h,
                       std::mt19937& rng) {
  mesh::TetMesh m = base;
  std::uniform_real_distribution<double> d(-0.1 * h, 0.1 * h);
  for (auto& x : m.vertices) {
    const bool boundary = ((x - lo).array().abs() < 1e-9).any() || ((x - hi).array().abs() < 1e-9).any();
    const Eigen::Vector3d off(d(rng), d(rng), d(rng));
    if (!boundary) x += off;
  }
  return m;
}

const char* scheme_name(fluid::AdvectionScheme s) {
  return s == fluid::AdvectionScheme::kBfecc ? "BFECC" : s == fluid::AdvectionScheme::kLinear ? "tet-linear" : "semi-Lagrangian";
}

/// Closed unit box with n^3 cells, a swirl, re-jittered every step: per-phase times.
void scaling(int n, fluid::SolverBackend backend, fluid::AdvectionScheme scheme, int steps) {
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  const double h = 1.0 / n, pi = std::acos(-1.0);
  const mesh::TetMesh base = mesh::structured_box(lo, hi, n, n, n);
  std::mt19937 rng(1);
  fluid::FluidParams p;
  p.solver.backend = backend;
  p.advection = scheme;
  p.solver.tolerance = 1e-8;
  fluid::FluidSolver s(p);
  s.initialize(jittered(base, lo, hi, h, rng));
  for (int t = 0; t < s.mesh().num_tets(); ++t) {
    const Eigen::Vector3d c = s.mesh().centroid(t);
    s.fields().velocity[t] = Eigen::Vector3d(std::sin(pi * c.x()) * std::cos(pi * c.y()),
                                             -std::cos(pi * c.x()) * std::sin(pi * c.y()), 0.3 * std::sin(pi * c.z()));
  }
  s.project_only({}, 0.01);
  double adv = 0, asmb = 0, sol = 0, total = 0, div = 0;
  int iters = 0;
  for (int k = 0; k < steps; ++k) {
    const mesh::TetMesh m = jittered(base, lo, hi, h, rng);
    tetfsi::bench::Stopwatch w;
    const fluid::StepReport r = s.step(m, {}, 0.5 * h);
    total += w.seconds();
    adv += r.advect_seconds;
    asmb += r.assemble_seconds;
    sol += r.solve_seconds;
    iters += r.iterations;
    div = std::max(div, r.max_divergence * h);
  }
  const std::string name = fmt::format("step, jittered box, {}, {}", fluid::to_string(backend), scheme_name(scheme));
  tetfsi::bench::print_row(
      name, fmt::format("{} tets, {} nodes", s.mesh().num_tets(), s.mesh().num_nodes()),
      fmt::format("per step: advect {:.3f} s, assemble {:.3f} s, solve {:.3f} s ({} it); max|div| h/U {:.1e}",
                  adv / steps, asmb / steps, sol / steps, iters / steps, div),
      total / steps);
}

/// Dam break in a closed n x n/2 x n/4 box (2 m x 1 m x 0.5 m), the column a quarter of its
/// length and 0.6 of its height, jittered Kuhn tets, static mesh: seconds per phase of a
/// free-surface step (surface tracking, advect, assemble, solve), steps 6-10 after 5 steps of run-up
/// at CFL 0.8. Returns the seconds per step.
double liquid_scaling(int n) {
  const Eigen::Vector3d lo(0, 0, 0), hi(2, 1, 0.5);
  const double h = 2.0 / n;
  std::mt19937 rng(3);
  const mesh::TetMesh m = jittered(mesh::structured_box(lo, hi, n, n / 2, n / 4), lo, hi, h, rng);
  fluid::FluidParams p;
  p.density = 1000;
  p.gravity = Eigen::Vector3d(0, -9.81, 0);
  p.solver.tolerance = 1e-8;
  fluid::FluidSolver s(p);
  s.initialize(m);
  fluid::LiquidOptions liquid;
  liquid.band = 4 * h;
  const Eigen::Vector3d column_hi(0.5, 0.6, 0.5);
  s.set_liquid(fluid::sample_level_set(s.mesh(), [&](const Eigen::Vector3d& x) { return fluid::box_distance(x, lo - Eigen::Vector3d::Ones(), column_hi); }), liquid);
  double surface = 0, adv = 0, asmb = 0, sol = 0, total = 0, drift = 0;
  const int runup = 5, steps = 5;
  for (int k = 0; k < runup + steps; ++k) {
    double umax = std::sqrt(9.81 * h);
    for (const auto& u : s.fields().velocity) umax = std::max(umax, u.norm());
    tetfsi::bench::Stopwatch w;
    const fluid::StepReport r = s.step(m, {}, 0.8 * h / umax);
    if (k < runup) continue;
    total += w.seconds();
    surface += r.surface_seconds;
    adv += r.advect_seconds;
    asmb += r.assemble_seconds;
    sol += r.solve_seconds;
    drift = std::max(drift, std::abs(r.volume_drift));
  }
  tetfsi::bench::print_row(
      "free-surface step, dam break, static jittered box", fmt::format("{} tets, {} nodes", s.mesh().num_tets(), s.mesh().num_nodes()),
      fmt::format("per step: surface {:.3f} s, advect {:.3f} s, assemble {:.3f} s, solve {:.3f} s; drift {:.1e}/step",
                  surface / steps, adv / steps, asmb / steps, sol / steps, drift),
      total / steps);
  return total / steps;
}

/// Taylor-Green cells (tests/fluid/test_taylor_green.cpp) at finer meshes: KE loss rate over 1 s.
void taylor_green(int n, double dt, fluid::AdvectionScheme scheme) {
  const double pi = std::acos(-1.0), h = pi / n;
  const Eigen::Vector3d lo(0, 0, 0), hi(pi, pi, 2 * h);
  const mesh::TetMesh base = mesh::structured_box(lo, hi, n, n, 2);
  std::mt19937 rng(9);
  fluid::FluidParams p;
  p.apply_gravity = false;
  p.advection = scheme;
  p.solver.tolerance = 1e-10;
  fluid::FluidSolver s(p);
  tetfsi::bench::Stopwatch w;
  s.initialize(jittered(base, lo, hi, h, rng));
  for (int t = 0; t < s.mesh().num_tets(); ++t) {
    const Eigen::Vector3d c = s.mesh().centroid(t);
    s.fields().velocity[t] = Eigen::Vector3d(std::sin(c.x()) * std::cos(c.y()), -std::cos(c.x()) * std::sin(c.y()), 0);
  }
  const double e0 = s.project_only({}, dt).kinetic_energy;
  double e = e0;
  const int steps = static_cast<int>(std::lround(1.0 / dt));
  for (int k = 0; k < steps; ++k) e = s.step(jittered(base, lo, hi, h, rng), {}, dt).kinetic_energy;
  tetfsi::bench::print_row(
      fmt::format("Taylor-Green, jittered every step, {}", scheme_name(scheme)),
      fmt::format("{} tets, h = pi/{}, dt = {}", s.mesh().num_tets(), n, dt),
      fmt::format("KE loss rate {:.4f} /s (exact 0)", (e0 - e) / e0), w.seconds());
}

/// Still water, 20 jittered steps: max |u| / sqrt(gH) and pressure error vs rho g depth.
void hydrostatic(int n) {
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  const double h = 1.0 / n, g = 9.81, rho = 1000.0;
  const mesh::TetMesh base = mesh::structured_box(lo, hi, n, n, n);
  std::mt19937 rng(3);
  fluid::FluidParams p;
  p.density = rho;
  p.solver.tolerance = 1e-12;
  fluid::FluidSolver s(p);
  tetfsi::bench::Stopwatch w;
  s.initialize(jittered(base, lo, hi, h, rng));
  double umax = 0, perr = 0;
  for (int k = 0; k < 20; ++k) {
    s.step(jittered(base, lo, hi, h, rng), {}, 0.01);
    for (const auto& u : s.fields().velocity) umax = std::max(umax, u.norm());
    double top = 0;
    int ntop = 0;
    for (int i = 0; i < s.mesh().num_nodes(); ++i)
      if (std::abs(s.mesh().nodes[i].z() - 1.0) < 1e-12) top += s.pressure()[i], ++ntop;
    top /= ntop;
    for (int i = 0; i < s.mesh().num_nodes(); ++i)
      perr = std::max(perr, std::abs(s.pressure()[i] - top - rho * g * (1.0 - s.mesh().nodes[i].z())) / (rho * g));
  }
  tetfsi::bench::print_row("hydrostatic, 20 jittered steps", fmt::format("{} tets", s.mesh().num_tets()),
                           fmt::format("max|u|/sqrt(gH) {:.1e}, max|p - rho g d|/(rho g H) {:.1e}", umax / std::sqrt(g), perr),
                           w.seconds());
}

}  // namespace

void sphere_cases(double h_near, double h_far, int steps) {
  const double a = 0.5, L = 1.0;
  tetfsi::bench::Stopwatch wm;
  const mesh::TetMesh m = fluid::validation::sphere_in_box(a, L, h_near, h_far);
  tetfsi::bench::print_row("CGAL complex mesh, sphere in box", fmt::format("{} tets", m.num_tets()), "-", wm.seconds());
  {
    tetfsi::bench::Stopwatch w;
    const auto r = fluid::validation::potential_flow(m, a, L);
    tetfsi::bench::print_row("potential flow past a sphere, surface Cp vs 1 - 9/4 sin^2",
                             fmt::format("{} tets, {} nodes, h_surface/a = {:.3f}", r.tets, r.nodes, r.h_surface / a),
                             fmt::format("rms {:.4f}, max {:.4f}; Cp stagnation {:.3f} (1), equator {:.3f} (-1.25)",
                                         r.surface_rms, r.surface_max, r.cp_stagnation, r.cp_equator),
                             w.seconds());
  }
  for (auto scheme : {fluid::AdvectionScheme::kLinear, fluid::AdvectionScheme::kBfecc}) {
    tetfsi::bench::Stopwatch w;
    const auto r = fluid::validation::added_mass(m, a, L, steps, scheme);
    tetfsi::bench::print_row(
        fmt::format("added mass, oscillating sphere, {} steps/period, {}", steps, scheme_name(scheme)),
        fmt::format("{} tets, h_near/a = {:.2f}", r.tets, h_near / a),
        fmt::format("m/(rho V/2) - 1 = {:+.4f} (impulsive start {:+.4f})", r.measured / r.ideal - 1.0,
                    r.impulsive / r.ideal - 1.0),
        w.seconds());
    if (steps == 0) break;
  }
}

/// Standing wave (standing_wave.hpp) at n cells per tank length: period against linear theory.
void standing_wave_case(int n) {
  tetfsi::bench::Stopwatch w;
  const tetfsi::bench::StandingWaveResult r = tetfsi::bench::standing_wave(n);
  tetfsi::bench::print_row(
      "standing wave (free surface, kH = pi/2)", fmt::format("{} cells/L, {} tets, {} steps", n, r.tets, r.steps),
      fmt::format("period {:+.2f}% vs omega^2 = g k tanh(kH); amplitude decay {:.1f}%/period; volume drift {:.1e}/step",
                  100 * (r.period / r.period_theory - 1), 100 * r.decay_per_period, r.max_volume_drift),
      w.seconds());
}

/// The sloshing tank of issue-style tests (L = 0.8 m, W = 0.1 m, H = 0.3 m, a = 5 mm, inviscid; linear
/// theory f = sqrt(g k tanh kH) / 2 pi = 0.89825 Hz) at n cells per length, `spp` steps per period,
/// over `periods` periods, with the velocity carried by `scheme` ("linear", "apic", "flip").
void sloshing_case(int n, int spp, double periods, const std::string& scheme) {
  tetfsi::bench::StandingWaveSetup setup;
  setup.length = 0.8;
  setup.width = 0.1;
  setup.depth = 0.3;
  setup.amplitude = 0.005;
  setup.cells = n;
  setup.periods = periods;
  setup.steps_per_period = spp;
  if (scheme == "apic") setup.particles.transfer = fluid::ParticleTransfer::kApic;
  if (scheme == "flip") setup.particles.transfer = fluid::ParticleTransfer::kFlip;
  tetfsi::bench::Stopwatch w;
  const tetfsi::bench::StandingWaveResult r = tetfsi::bench::standing_wave(setup);
  tetfsi::bench::print_row(
      fmt::format("sloshing tank, {}, T/{}, {:g} periods", scheme, spp, periods),
      fmt::format("{} cells/L, {} tets{}", n, r.tets, r.particles > 0 ? fmt::format(", {} particles", r.particles) : ""),
      fmt::format("frequency {:+.2f}%, energy {:+.2f}%/period, amplitude {:+.2f}%/period; particle phase {:.1f}% of the time",
                  100 * (r.period_theory / r.period - 1), -100 * r.energy_loss_per_period, -100 * r.decay_per_period,
                  100 * r.particle_seconds / w.seconds()),
      w.seconds());
}

/// The comma-separated items of a list option.
std::vector<std::string> parse_list(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  return items;
}

/// The comma-separated numbers of `--sizes`.
std::vector<double> parse_sizes(const std::string& list) {
  std::vector<double> sizes;
  std::stringstream items(list);
  for (std::string item; std::getline(items, item, ',');) sizes.push_back(std::stod(item));
  return sizes;
}

int main(int argc, char** argv) {
  long max_tets = 450000;
  bool sphere_only = false, scaling_only = false, standing_wave = false, sloshing = false;
  std::vector<double> sizes, steps_per_period{40, 80};
  std::vector<std::string> schemes{"linear", "apic", "flip"};
  double periods = 20;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--sizes") == 0 && i + 1 < argc) sizes = parse_sizes(argv[i + 1]);
    if (std::strcmp(argv[i], "--standing-wave") == 0) standing_wave = true;
    if (std::strcmp(argv[i], "--sloshing") == 0) sloshing = true;
    if (std::strcmp(argv[i], "--steps-per-period") == 0 && i + 1 < argc) steps_per_period = parse_sizes(argv[i + 1]);
    if (std::strcmp(argv[i], "--schemes") == 0 && i + 1 < argc) schemes = parse_list(argv[i + 1]);
    if (std::strcmp(argv[i], "--periods") == 0 && i + 1 < argc) periods = std::atof(argv[i + 1]);
  }
  if (sloshing) {
    tetfsi::bench::print_header();
    for (double n : sizes.empty() ? std::vector<double>{16, 24, 32, 48} : sizes)
      for (double spp : steps_per_period)
        for (const std::string& scheme : schemes) sloshing_case(static_cast<int>(n), static_cast<int>(spp), periods, scheme);
    return 0;
  }
  if (standing_wave) {
    tetfsi::bench::print_header();
    for (double n : sizes.empty() ? std::vector<double>{16, 32, 64} : sizes) standing_wave_case(static_cast<int>(n));
    return 0;
  }
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--max-tets") == 0 && i + 1 < argc) max_tets = std::atol(argv[i + 1]);
    if (std::strcmp(argv[i], "--sphere-only") == 0) sphere_only = true;
    if (std::strcmp(argv[i], "--scaling-only") == 0) scaling_only = true;
    if (std::strcmp(argv[i], "--liquid") == 0) {
      tetfsi::bench::print_header();
      std::vector<std::pair<long, double>> cost;
      for (int n : {32, 51, 81}) {
        if (6L * n * (n / 2) * (n / 4) > max_tets) continue;
        const double t = liquid_scaling(n);
        cost.emplace_back(6L * n * (n / 2) * (n / 4), t);
      }
      if (cost.size() >= 2)
        fmt::print("growth of the free-surface step: n^{:.2f} from {} to {} tets\n",
                   std::log(cost.back().second / cost.front().second) /
                       std::log(double(cost.back().first) / double(cost.front().first)),
                   cost.front().first, cost.back().first);
      return 0;
    }
  }
  tetfsi::bench::print_header();
  if (!scaling_only)
    for (double hn : sizes.empty() ? std::vector<double>{0.12, 0.08, 0.055} : sizes)
      sphere_cases(hn, 2.0 * hn, sphere_only ? 0 : 40);
  if (sphere_only) return 0;
  for (int n : {16, 26, 41}) {
    if (6L * n * n * n > max_tets) continue;
    scaling(n, fluid::SolverBackend::kHypreAmgCg, fluid::AdvectionScheme::kLinear, 3);
    scaling(n, fluid::SolverBackend::kEigenIcCg, fluid::AdvectionScheme::kLinear, 3);
    scaling(n, fluid::SolverBackend::kHypreAmgCg, fluid::AdvectionScheme::kBfecc, 3);
  }
  if (scaling_only) return 0;
  for (int n : {16, 32, 64})
    for (auto scheme : {fluid::AdvectionScheme::kSemiLagrangian, fluid::AdvectionScheme::kBfecc,
                        fluid::AdvectionScheme::kLinear})
      taylor_green(n, 0.05, scheme);
  hydrostatic(std::min(20, static_cast<int>(std::cbrt(max_tets / 6.0))));
  for (int n : {16, 32, 64}) standing_wave_case(n);
  return 0;
}
