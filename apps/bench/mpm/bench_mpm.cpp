// bench_mpm: one table (case, resolution, error vs reference, wall time, peak memory) for the MPM
// subsystem. Extra lines starting with '#' give the tracked quantities (Fig. 11 convergence study,
// Fig. 16 radii). Usage: bench_mpm [--cases bar,disks,gas,fig11,membrane_on_sphere,water,sphere_steps]
//                                  [--gas-t-end 4] [--sphere-t-end 0.4e-3] [--threads N] [--stats-dir DIR]
// The paper examples run at the paper's resolution and the committed scenes' end times by default;
// The paper examples are the committed scenes (data/scenes/), run by the mpm runner's model;
// each row reports particle updates (particles x coupled steps) per second of wall and of CPU time.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <set>
#include <sstream>

#include "apps/bench/bench_support.hpp"
#include "apps/mpm/probes.hpp"
#include "apps/mpm/setup.hpp"
#include "apps/scene/scene.hpp"
#include "fluid/mpm/mpm_solver.hpp"

#include <sys/resource.h>

using namespace tetfsi;
using mpm::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec + 1e-6 * u.ru_stime.tv_usec;
}

void bench_bar() {
  bench::Stopwatch sw;
  const double L = 25, E = 100, rho = 1, v0 = 0.1;
  const int cells = 13;
  const double h = L / cells, beta = kPi / (2 * L), c = std::sqrt(E / rho);
  mpm::Grid g;
  g.dx = h;
  g.cells = {cells + 2, 1, 1};
  g.faces[0] = mpm::FaceBc::Slip;
  g.constrained_axes = {false, true, true};
  mpm::Particles P;
  for (int i = 0; i < cells; ++i) {
    const Vec3 x((i + 0.5) * h, 0.5 * h, 0.5 * h);
    P.add(rho * h * h * h, x, Vec3(v0 * std::sin(beta * x[0]), 0, 0), rho, 0, 0);
  }
  mpm::MpmSolver s(g, {mpm::Material::linear_elastic(rho, E, 0.0)}, P);
  const double dt = 0.1 * h / c, omega = beta * c;
  std::vector<double> crossings;
  double prev = v0, t = 0, peak_last = 0;
  double total_mass = 0;
  for (double m : s.particles().mass) total_mass += m;
  // Centre-of-mass velocity along the bar (MpmSolver::total_momentum / mass).
  auto mean_v = [&] { return s.total_momentum()[0] / total_mass; };
  prev = mean_v();
  const double first = std::abs(prev);
  while (t < 10 * 2 * kPi / omega) {
    s.step(dt);
    t += dt;
    const double cur = mean_v();
    if ((prev > 0) != (cur > 0)) crossings.push_back(t - dt / 2 - dt * cur / (cur - prev));
    if (t > 9 * 2 * kPi / omega) peak_last = std::max(peak_last, std::abs(cur));  // last period
    prev = cur;
  }
  const double w = kPi * (crossings.size() - 1) / (crossings.back() - crossings.front());
  bench::print_row("1D vibrating bar (bm 5.2)", "13 cells, 1 ppc, 10 periods",
                   fmt::format("omega {:.5f} vs {:.5f}: {:+.2e} rel.; amplitude after 10 periods / initial {:.4f}", w, omega,
                               w / omega - 1, peak_last / first),
                   sw.seconds());
}

void bench_disks() {
  bench::Stopwatch sw;
  const double h = 0.05, dx = h / 2, r = 0.2, rho = 1000;
  mpm::Grid g;
  g.lo = Vec3(-0.1, -0.1, 0);
  g.dx = h;
  g.cells = {24, 24, 1};
  g.constrained_axes = {false, false, true};
  mpm::Particles P;
  for (int d = 0; d < 2; ++d) {
    const Vec3 c = (d == 0 ? Vec3(0.2, 0.2, 0) : Vec3(0.8, 0.8, 0)) + Vec3(0.00123, 0.00123, 0);
    const Vec3 v = d == 0 ? Vec3(0.1, 0.1, 0) : Vec3(-0.1, -0.1, 0);
    const std::size_t first = P.size();
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i) {
        const Vec3 x = c + Vec3(-r + (i + 0.5) * dx, -r + (j + 0.5) * dx, 0);
        if ((x - c).head<2>().norm() < r) P.add(0, Vec3(x[0], x[1], 0.5 * h), v, rho, 0, 0);
      }
    for (std::size_t p = first; p < P.size(); ++p) P.mass[p] = rho * kPi * r * r * h / double(P.size() - first);
  }
  mpm::MpmSolver s(g, {mpm::Material::linear_elastic(rho, 1000, 0.3)}, P);
  const double e0 = s.energies().total() / h;
  double emin = e0, emax = e0;
  for (int n = 0; n < 3000; ++n) {
    s.step(0.001);
    const double e = s.energies().total() / h;
    emin = std::min(emin, e);
    emax = std::max(emax, e);
  }
  bench::print_row("colliding disks (bm 5.1)", "20x20 cells, 4 ppc, dt 1e-3, t 3",
                   fmt::format("KE0 {:.4f} (2.513); total energy in [{:+.2f}%, {:+.2f}%], final {:+.2f}%", e0,
                               100 * (emin / e0 - 1), 100 * (emax / e0 - 1), 100 * (s.energies().total() / h / e0 - 1)),
                   sw.seconds());
}

/// A committed mpm scene (data/scenes/<name>.json) run to t_end with `patch` applied to its
/// resolved /mpm block: the tracked probes every t_end / 8, then one row with the final probes,
/// the energy lost and booked as contact dissipation, the coupled steps and the throughput.
void bench_scene(const std::string& scene_name, const std::string& label, double t_end,
                 const std::function<void(scene::Json&)>& patch, const std::string& stats_dir) {
  bench::Stopwatch sw;
  const double cpu0 = cpu_seconds();
  const auto sc = scene::load_scene(std::filesystem::path(TETFSI_SOURCE_DIR) / "data" / "scenes" / (scene_name + ".json"));
  scene::Json m = sc["mpm"];
  if (patch) patch(m);
  const auto& g = sc["simulation"]["gravity"];
  const auto setup = mpm_setup::build_setup(m, Vec3(g[0].get<double>(), g[1].get<double>(), g[2].get<double>()));
  const auto probes = mpm_setup::resolve_probes(setup, sc["probes"]);
  auto model = mpm_setup::make_model(setup);
  std::unique_ptr<std::ofstream> stats;
  if (!stats_dir.empty()) {
    std::filesystem::create_directories(stats_dir);
    stats = std::make_unique<std::ofstream>(std::filesystem::path(stats_dir) / (label + "_stats.csv"));
    *stats << "step,time,dt,contact_nodes,stored_energy,contact_dissipation,energy_balance";
    for (const auto& p : sc["probes"]) *stats << "," << p.at("name").get<std::string>();
    *stats << "\n";
  }
  auto values = [&] {
    std::string s;
    for (std::size_t i = 0; i < probes.size(); ++i)
      s += fmt::format(" {}={:.6g}", sc["probes"][i].at("name").get<std::string>(), mpm_setup::evaluate(probes[i], setup, *model));
    return s;
  };
  const double e0 = model->stored_energy();
  std::vector<double> lowest(probes.size());  // smallest value of each position probe over the steps
  for (std::size_t i = 0; i < probes.size(); ++i) lowest[i] = mpm_setup::evaluate(probes[i], setup, *model);
  std::ostringstream hist;
  double t = 0, next = 0;
  long steps = 0;
  const std::size_t particles0 = model->mpm().particles().size();
  long particle_updates = 0;
  while (t < t_end * (1 - 1e-12)) {
    if (t >= next - 1e-12 * t_end) {
      hist << fmt::format("#   t={:.6g}{}\n", t, values());
      next += t_end / 8;
    }
    const double dt = std::min(model->max_dt(), t_end - t);
    const auto rep = model->step(dt);
    t += dt;
    ++steps;
    particle_updates += static_cast<long>(model->mpm().particles().size());
    for (std::size_t i = 0; i < probes.size(); ++i)  // positions only: energies would cost a particle pass
      if (probes[i].kind != mpm_setup::Probe::Kind::TotalEnergy && probes[i].kind != mpm_setup::Probe::Kind::BodyEnergy)
        lowest[i] = std::min(lowest[i], mpm_setup::evaluate(probes[i], setup, *model));
    if (stats && steps % 50 == 0) {
      const auto e = model->coupling().energies();
      *stats << fmt::format("{},{:.9g},{:.6g},{},{:.9g},{:.9g},{:.9g}", steps, t, dt, rep.contact_nodes,
                            mpm_contact::CoupledModel::stored_energy(e), e.contact, model->balance(e));
      for (const auto& p : probes) *stats << fmt::format(",{:.9g}", mpm_setup::evaluate(p, setup, *model));
      *stats << "\n";
    }
  }
  hist << fmt::format("#   t={:.6g}{}\n", t, values());
  const double wall = sw.seconds(), cpu = cpu_seconds() - cpu0;
  const auto e = model->coupling().energies();
  std::string minima;
  for (std::size_t i = 0; i < probes.size(); ++i)
    if (probes[i].kind != mpm_setup::Probe::Kind::TotalEnergy && probes[i].kind != mpm_setup::Probe::Kind::BodyEnergy)
      minima += fmt::format(" {}={:.6g}", sc["probes"][i].at("name").get<std::string>(), lowest[i]);
  fmt::print("# {} ({}): probes (scene {})\n{}", label, scene_name, scene_name, hist.str());
  bench::print_row(label,
                   fmt::format("cell {} m, {} particles, {} quads, t {}", setup.grid.dx, particles0,
                               model->membrane().num_elements(), t_end),
                   fmt::format("final{}; min over the steps (positions){}; energy lost {:.2f}%, booked as contact dissipation {:.2f}%; {} steps, {:.3g} particle "
                               "upd/s wall, {:.3g} per cpu s, cpu {:.1f} s",
                               values(), minima, 100 * (1 - model->stored_energy() / e0), 100 * e.contact / e0, steps,
                               particle_updates / wall, particle_updates / cpu, cpu),
                   wall);
}

/// Grid of the section-7.1 sphere-on-membrane scene at another cell size (Fig. 11): the membrane
/// square with a margin of two cells, z from -25 mm to the sphere top + 4 cells, the lower corner
/// moved down by the part of a spacing that puts the particle lattice at in-cell positions
/// (i + 1/2) / n of the cells, never on node planes (coupling/mpm/README.md).
void sphere_on_membrane_grid(scene::Json& m, double cell) {
  const double mm = 1e-3, half = 25 * mm, R = 4.5 * mm, zc = 5.5 * mm, dx = 0.5 * mm, margin = 2 * cell;
  Vec3 lo(-half - margin, -half - margin, -25 * mm);
  const Vec3 hi(half + margin, half + margin, zc + R + 4 * cell), box_lo(-R, -R, zc - R);
  for (int a = 0; a < 3; ++a) {
    const double s = (box_lo[a] - lo[a]) / dx, r = s - std::floor(s);
    if (r > 1e-9 && r < 1 - 1e-9) lo[a] -= (1 - r) * dx;
  }
  m["grid"]["lo"] = {lo[0], lo[1], lo[2]};
  m["grid"]["hi"] = {hi[0], hi[1], hi[2]};
  m["grid"]["cell"] = cell;
  m["membrane"]["element_size"] = cell;
}

/// Cost of the MPM particle passes alone, at the size of the section-7.1 sphere (R = 15 mm,
/// E = 70 GPa, rho = 2750 kg/m^3, cell 1 mm, spacing 0.5 mm: 113,104 particles) translating at
/// 1 m/s: no membrane, no contact. Reference: a rigid translation keeps its velocity and stays
/// stress-free; the row gives max |v_p - v0| / |v0| and the strain energy over the kinetic energy.
/// The wall time per step is the best of 5 repetitions of 20 steps (the machine's speed drifts).
void bench_sphere_steps() {
  bench::Stopwatch sw;
  const double R = 15e-3, h = 1e-3, dx = 0.5e-3, rho = 2750;
  const Vec3 centre(0, 0, 15e-3), v0(0, 0, -1.0);
  const mpm::Grid grid = mpm::Grid::covering(Vec3(-30e-3, -30e-3, 0), Vec3(30e-3, 30e-3, 40e-3), h);
  mpm::Particles P;
  mpm::sample_lattice(P, centre - Vec3(R, R, R), centre + Vec3(R, R, R), dx, rho, 0, v0, 0,
                      [&](const Vec3& x) { return (x - centre).norm() < R; });
  mpm::MpmSolver s(grid, {mpm::Material::linear_elastic(rho, 70e9, 0.3)}, P);
  const double dt = s.critical_time_step();
  for (int n = 0; n < 2; ++n) s.step(dt);
  double best = 1e300;
  for (int rep = 0; rep < 5; ++rep) {
    bench::Stopwatch w;
    for (int n = 0; n < 20; ++n) s.step(dt);
    best = std::min(best, w.seconds() / 20);
  }
  double dv = 0;
  for (const auto& v : s.particles().v) dv = std::max(dv, (v - v0).norm());
  const auto e = s.energies();
  bench::print_row("elastic sphere, MPM passes only (7.1 sphere, rigid translation)",
                   fmt::format("cell 1 mm, spacing 0.5 mm, {} particles, 102 steps", P.size()),
                   fmt::format("max |v - v0| / |v0| {:.1e}, strain / kinetic energy {:.1e}; best step {:.2f} ms, "
                               "{:.1f} ns per particle-step (wall)",
                               dv / v0.norm(), e.internal / e.kinetic, best * 1e3, best / double(P.size()) * 1e9),
                   sw.seconds());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"MPM / membrane / grid-contact benchmark (Lian, Liu & Zhang 2014)"};
  std::string cases = "bar,disks,gas,fig11";
  double gas_t_end = 4.0;  // settled by t = 3 in the coarse run
  double sphere_t_end = 0.4e-3;  // the scenes' end time
  int threads = 0;
  std::string stats_dir;
  app.add_option("--cases", cases, "comma list of bar,disks,gas,gas_coarse,fig11,membrane_on_sphere,water,sphere_steps");
  app.add_option("--gas-t-end", gas_t_end, "end time of the gas expansion (dimensionless)");
  app.add_option("--sphere-t-end", sphere_t_end, "end time of membrane_on_sphere and water [s]");
  double mos_cfl = 0.9;  // as data/scenes/membrane_on_sphere.json (coupling/mpm/README.md, "The MPM step")
  app.add_option("--mos-cfl", mos_cfl, "mpm_cfl of membrane_on_sphere (the scene's 0.9)")->check(CLI::Range(1e-3, 1.0));
  app.add_option("--threads", threads, "worker threads (0: every core)");
  app.add_option("--stats-dir", stats_dir, "write <case>_stats.csv files there");
  CLI11_PARSE(app, argc, argv);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            threads > 0 ? static_cast<std::size_t>(threads)
                                        : tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  fmt::print("# threads: {}\n", tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  std::set<std::string> want;
  std::stringstream ss(cases);
  for (std::string c; std::getline(ss, c, ',');) want.insert(c);
  try {
    bench::print_header();
    if (want.count("bar")) bench_bar();
    if (want.count("disks")) bench_disks();
    if (want.count("gas_coarse"))
      bench_scene("gas_expansion", "gas expansion (paper 7.3, quarter), spacing 0.05", gas_t_end,
                  [](scene::Json& m) { m["bodies"][0]["spacing"] = 0.05; }, stats_dir);
    if (want.count("gas"))
      bench_scene("gas_expansion", "gas expansion (paper 7.3, quarter)", gas_t_end, nullptr, stats_dir);
    if (want.count("fig11"))
      for (double cell : {2e-3, 1.5e-3, 1e-3})
        bench_scene("sphere_on_membrane", fmt::format("sphere on membrane (7.1, Fig. 11), cell {} mm", cell * 1e3), 0.4e-3,
                    [cell](scene::Json& m) { sphere_on_membrane_grid(m, cell); }, stats_dir);
    if (want.count("membrane_on_sphere"))
      bench_scene("membrane_on_sphere", "membrane on sphere (7.1, Fig. 6)", sphere_t_end,
                  [mos_cfl](scene::Json& m) { m["mpm_cfl"] = mos_cfl; }, stats_dir);
    if (want.count("sphere_steps")) bench_sphere_steps();
    if (want.count("water"))
      bench_scene("water_sphere", "water sphere (7.2, Fig. 12)", sphere_t_end, nullptr, stats_dir);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_mpm: {}\n", e.what());
    return 1;
  }
  return 0;
}
