// bench_solid: speed and accuracy of the tet FEM + Newmark integrator (issue 3).
//  1. Implicit step time, split into assembly (K, K', A, b) and solve, for ~1k, 10k, 100k tets:
//     a cube of StVK tets clamped at the bottom, sagging under gravity (h = 1/30 s).
//  2. Cantilever (L = 1 m, b = 0.1 m, E = 1 MPa, nu = 0) against Euler-Bernoulli
//     (tip P L^3 / (3 E I), beta_1 L = 1.875104): static tip deflection and first bending frequency per refinement level.
//  3. With --calculix: the same static cantilever meshes in CalculiX (ccx, C3D4), side by side.
// Usage: bench_solid [--max-level N] [--steps N] [--calculix]
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <stdlib.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "apps/bench/bench_support.hpp"
#include "mesh/structured_box.hpp"
#include "solid/analysis/linear_analysis.hpp"
#include "solid/integrator/spd_solver.hpp"
#include "solid/integrator/newmark.hpp"
#include "apps/fixtures/cantilever.hpp"
#include "solid/tet/tet_model.hpp"

using namespace tetfsi;
using namespace tetfsi::solid;

namespace {

/// CPU time of this process (all threads) [s]: on the shared 2-core machine the wall time of a
/// step depends on the other jobs; the CPU time much less.
double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double load_average() {
  double load[1] = {0};
  return getloadavg(load, 1) == 1 ? load[0] : -1;
}

void bench_steps(int cells, int steps, SolverKind solver, int beam_ratio = 1) {
  bench::Stopwatch total;
  // beam_ratio > 1: a slender beam (beam_ratio * cells) x cells x cells instead of the cube.
  const auto mesh = mesh::structured_box({0, 0, 0}, {double(beam_ratio), 1, 1}, beam_ratio * cells, cells, cells);
  TetMaterial mat;
  mat.youngs_modulus = 1e5;
  mat.poisson_ratio = 0.3;
  mat.density = 1000;
  TetModel model(mesh, mat);
  NewmarkSettings settings;
  const double time_step = 1.0 / 30.0;
  settings.gravity = {0, 0, -9.81};
  settings.solver = solver;
  settings.cg_tolerance = 1e-8;
  settings.track_energy = false;
  NewmarkIntegrator integ(model, settings);
  if (beam_ratio > 1)
    integ.fix_nodes(integ.nodes_in_box({-1e-9, -1, -1}, {1e-9, 2, 2}));
  else
    integ.fix_nodes(integ.nodes_in_box({-1, -1, -1e-9}, {2, 2, 1e-9}));
  integ.step(time_step);  // first step includes the symbolic analysis; not timed
  double assembly = 0, solve = 0, iterations = 0;
  bench::Stopwatch sw;
  const double cpu0 = cpu_seconds();
  for (int n = 0; n < steps; ++n) {
    const auto& st = integ.step(time_step);
    assembly += st.assembly_seconds;
    solve += st.solve_seconds;
    iterations += st.solver_iterations;
  }
  const double per_step = sw.seconds() / steps;
  const double cpu_per_step = (cpu_seconds() - cpu0) / steps;
  const double sag = -integ.displacement().minCoeff();
  bench::print_row(fmt::format("implicit step, StVK {}, {} (per step: {:.1f} ms; assembly {:.1f} ms, solve {:.1f} ms, "
                               "{:.0f} it.; CPU {:.1f} ms/step; load avg {:.1f})",
                               beam_ratio > 1 ? "beam, clamped end" : "cube, clamped base",
                               solver == SolverKind::kCholmod ? "CHOLMOD" : solver == SolverKind::kConjugateGradient ? "CG+Jacobi" : "CG+IC", 1e3 * per_step,
                               1e3 * assembly / steps, 1e3 * solve / steps, iterations / steps, 1e3 * cpu_per_step,
                               load_average()),
                   fmt::format("{} tets, {} nodes", model.num_tets(), model.num_nodes()),
                   fmt::format("n/a (max sag {:.3g} m)", sag), total.seconds());
}

void bench_cantilever(int m) {
  bench::Stopwatch total;
  const CantileverSpec spec = slender_cantilever_spec(m);
  const auto beam = make_cantilever(spec);
  const double P = 1e-3;
  const Eigen::VectorXd d = solve_linear_static(*beam.model, beam.fixed_dofs, beam.tip_load({0, 0, -P}));
  const double static_seconds = total.seconds();
  const double w = -beam.tip_displacement(d, 2);
  const double err_w = w / beam.euler_bernoulli_deflection(P) - 1;
  bench::print_row("cantilever static tip deflection vs PL^3/(3EI)",
                   fmt::format("{}x{}x{} cells, {} tets", 10 * m, m, m, beam.model->num_tets()),
                   fmt::format("{:+.4f} rel. (tip {:.6e} m)", err_w, w), static_seconds);
  bench::Stopwatch modal;
  const Mode mode = lowest_mode(*beam.model, beam.fixed_dofs, d, 1e-9);
  const double err_f = mode.omega / beam.euler_bernoulli_omega1() - 1;
  bench::print_row("cantilever first bending frequency vs 1.875104^2 sqrt(EI/(rho A L^4))",
                   fmt::format("{}x{}x{} cells, {} tets", 10 * m, m, m, beam.model->num_tets()),
                   fmt::format("{:+.4f} rel. ({} subspace iterations)", err_f, mode.iterations), modal.seconds());
}

/// Same static cantilever in CalculiX (C3D4 linear tets, identical mesh, clamp and tip
/// loads), when `ccx` is on the PATH (Debian package calculix-ccx). Returns false if absent.
bool bench_calculix(int m) {
  if (std::system("command -v ccx > /dev/null 2>&1") != 0) return false;
  const CantileverSpec spec = slender_cantilever_spec(m);
  const auto beam = make_cantilever(spec);
  const double P = 1e-3;
  char dir_template[] = "/tmp/tetfsi_ccx_XXXXXX";
  const char* dir = mkdtemp(dir_template);
  if (!dir) return false;
  const std::string base = std::string(dir) + "/beam";
  {
    std::ofstream inp(base + ".inp");
    inp.precision(12);  // ccx reads numbers from fields of at most 20 characters
    inp << "*NODE\n";
    for (int v = 0; v < beam.mesh.num_vertices(); ++v) {
      const auto& x = beam.mesh.vertices[v];
      inp << v + 1 << ", " << x.x() << ", " << x.y() << ", " << x.z() << "\n";
    }
    inp << "*ELEMENT, TYPE=C3D4, ELSET=EALL\n";
    for (int t = 0; t < beam.mesh.num_tets(); ++t) {
      const auto& e = beam.mesh.tets[t];
      inp << t + 1 << ", " << e[0] + 1 << ", " << e[1] + 1 << ", " << e[2] + 1 << ", " << e[3] + 1 << "\n";
    }
    auto write_set = [&](const std::string& name, const std::vector<int>& nodes) {
      inp << "*NSET, NSET=" << name << "\n";
      for (size_t k = 0; k < nodes.size(); ++k) inp << nodes[k] + 1 << ((k % 8 == 7 || k + 1 == nodes.size()) ? "\n" : ", ");
    };
    std::vector<int> tip;
    for (int v = 0; v < beam.mesh.num_vertices(); ++v)
      if (beam.tip_weights[v] > 0) tip.push_back(v);
    write_set("FIX", beam.clamped_nodes);
    write_set("TIP", tip);
    inp << "*BOUNDARY\nFIX, 1, 3\n*MATERIAL, NAME=M\n*ELASTIC\n" << spec.material.youngs_modulus << ", 0.0\n"
        << "*SOLID SECTION, ELSET=EALL, MATERIAL=M\n*STEP\n*STATIC\n*CLOAD\n";
    for (int v : tip) inp << v + 1 << ", 3, " << -P * beam.tip_weights[v] << "\n";
    inp << "*NODE PRINT, NSET=TIP\nU\n*END STEP\n";
  }
  bench::Stopwatch sw;
  const int rc = std::system(("cd " + std::string(dir) + " && OMP_NUM_THREADS=1 ccx -i beam > ccx.log 2>&1").c_str());
  const double seconds = sw.seconds();
  std::ifstream dat(base + ".dat");
  std::string line;
  double w = 0;
  int count = 0;
  while (std::getline(dat, line)) {
    std::istringstream ls(line);
    int node;
    double ux, uy, uz;
    if (ls >> node >> ux >> uy >> uz) {
      w += beam.tip_weights[node - 1] * -uz;
      ++count;
    }
  }
  if (rc != 0 || count == 0) {
    bench::print_row("CalculiX ccx static cantilever (C3D4)", fmt::format("{} tets", beam.model->num_tets()),
                     fmt::format("FAILED (exit {}, see {}/ccx.log)", rc, dir), seconds);
    return true;
  }
  bench::print_row("CalculiX ccx 2.20 static cantilever, same mesh (C3D4), 1 thread",
                   fmt::format("{}x{}x{} cells, {} tets", 10 * m, m, m, beam.model->num_tets()),
                   fmt::format("{:+.4f} rel. vs EB (tip {:.6e} m)", w / beam.euler_bernoulli_deflection(P) - 1, w), seconds);
  std::system(("rm -rf " + std::string(dir)).c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tetfsi solid benchmark: implicit step timing and cantilever accuracy"};
  int max_level = 12;
  int steps = 10;
  app.add_option("--max-level", max_level, "finest cantilever level m (10m x m x m cells)");
  app.add_option("--steps", steps, "timed steps per size");
  bool calculix = false;
  app.add_flag("--calculix", calculix, "also run CalculiX (ccx) on the static cantilever");
  CLI11_PARSE(app, argc, argv);
  const bool openblas = limit_blas_threads(1);
  fmt::print("BLAS threads limited to 1: {}\n\n", openblas ? "yes (OpenBLAS)" : "no OpenBLAS found");
  bench::print_header();
  for (int cells : {6, 12}) bench_steps(cells, steps, SolverKind::kCholmod);
  bench_steps(26, std::min(steps, 3), SolverKind::kCholmod);
  bench_steps(6, steps, SolverKind::kCholmod, 10);   // 60x6x6 cells, 12960 tets
  bench_steps(12, steps, SolverKind::kConjugateGradient);
  bench_steps(12, steps, SolverKind::kConjugateGradientIC);
  bench_steps(26, std::min(steps, 3), SolverKind::kConjugateGradient);
  for (int m : {2, 4, 6, 8, 10, 12, 14})
    if (m <= max_level) bench_cantilever(m);
  if (calculix)
    for (int m : {4, 8})
      if (m <= max_level && !bench_calculix(m)) fmt::print("(ccx not found: CalculiX comparison skipped)\n");
  return 0;
}
