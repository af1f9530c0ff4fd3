// bench_solid: speed and accuracy of the tet FEM + trapezoidal integrator (issue 3).
//  1. Implicit step time, split into assembly (K, K', A, b) and solve, for ~1k, 10k, 100k tets:
//     a cube of StVK tets clamped at the bottom, sagging under gravity (h = 1/30 s).
//  2. Cantilever (L = 1 m, b = 0.1 m, E = 1 MPa, nu = 0) against Euler-Bernoulli
//     (benchmarks.md 3.4): static tip deflection and first bending frequency per refinement level.
// Usage: bench_solid [--max-level N] [--steps N]
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "apps/bench/bench_support.hpp"
#include "mesh/structured_box.hpp"
#include "solid/analysis/linear_analysis.hpp"
#include "solid/integrator/spd_solver.hpp"
#include "solid/integrator/trapezoidal.hpp"
#include "solid/scenarios/cantilever.hpp"
#include "solid/tet/tet_model.hpp"

using namespace tetfsi;
using namespace tetfsi::solid;

namespace {

void bench_steps(int cells, int steps, SolverKind solver) {
  bench::Stopwatch total;
  const auto mesh = mesh::structured_box({0, 0, 0}, {1, 1, 1}, cells, cells, cells);
  TetMaterial mat;
  mat.youngs_modulus = 1e5;
  mat.poisson_ratio = 0.3;
  mat.density = 1000;
  TetModel model(mesh, mat);
  TrapezoidalSettings settings;
  settings.time_step = 1.0 / 30.0;
  settings.gravity = {0, 0, -9.81};
  settings.solver = solver;
  settings.cg_tolerance = 1e-8;
  settings.track_energy = false;
  TrapezoidalIntegrator integ(model, settings);
  integ.fix_nodes(integ.nodes_in_box({-1, -1, -1e-9}, {2, 2, 1e-9}));
  integ.step();  // first step includes the symbolic analysis; not timed
  double assembly = 0, solve = 0, iterations = 0;
  bench::Stopwatch sw;
  for (int n = 0; n < steps; ++n) {
    const auto& st = integ.step();
    assembly += st.assembly_seconds;
    solve += st.solve_seconds;
    iterations += st.solver_iterations;
  }
  const double per_step = sw.seconds() / steps;
  const double sag = -integ.displacement().minCoeff();
  bench::print_row(fmt::format("implicit step, StVK cube, {} (per step: {:.1f} ms; assembly {:.1f} ms, solve {:.1f} ms, "
                               "{:.0f} it.)",
                               solver == SolverKind::kCholmod ? "CHOLMOD" : "CG+IC", 1e3 * per_step,
                               1e3 * assembly / steps, 1e3 * solve / steps, iterations / steps),
                   fmt::format("{} tets, {} nodes", model.num_tets(), model.num_nodes()),
                   fmt::format("n/a (max sag {:.3g} m)", sag), total.seconds());
}

void bench_cantilever(int m) {
  bench::Stopwatch total;
  CantileverSpec spec;
  spec.cells_across = m;
  spec.cells_along = 10 * m;
  spec.material.youngs_modulus = 1e6;
  spec.material.poisson_ratio = 0.0;
  spec.material.density = 1000;
  const auto beam = make_cantilever(spec);
  const double P = 1e-3;
  const Eigen::VectorXd d = solve_linear_static(*beam.model, beam.fixed_dofs, beam.tip_load({0, 0, -P}));
  const double static_seconds = total.seconds();
  const double w = -beam.tip_displacement(d, 2);
  const double err_w = w / beam.euler_bernoulli_deflection(P) - 1;
  bench::print_row("cantilever static tip deflection vs PL^3/(3EI)",
                   fmt::format("{}x{}x{} cells, {} tets", 10 * m, m, m, beam.model->num_tets()),
                   fmt::format("{:+.4f} rel.", err_w), static_seconds);
  bench::Stopwatch modal;
  const Mode mode = lowest_mode(*beam.model, beam.fixed_dofs, d, 1e-9);
  const double err_f = mode.omega / beam.euler_bernoulli_omega1() - 1;
  bench::print_row("cantilever first bending frequency vs 1.875104^2 sqrt(EI/(rho A L^4))",
                   fmt::format("{}x{}x{} cells, {} tets", 10 * m, m, m, beam.model->num_tets()),
                   fmt::format("{:+.4f} rel. ({} inverse iterations)", err_f, mode.iterations), modal.seconds());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tetfsi solid benchmark: implicit step timing and cantilever accuracy"};
  int max_level = 12;
  int steps = 10;
  app.add_option("--max-level", max_level, "finest cantilever level m (10m x m x m cells)");
  app.add_option("--steps", steps, "timed steps per size");
  CLI11_PARSE(app, argc, argv);
  const bool openblas = limit_blas_threads(1);
  fmt::print("BLAS threads limited to 1: {}\n\n", openblas ? "yes (OpenBLAS)" : "no OpenBLAS found");
  bench::print_header();
  for (int cells : {6, 12}) bench_steps(cells, steps, SolverKind::kCholmod);
  bench_steps(26, std::min(steps, 3), SolverKind::kCholmod);
  bench_steps(12, steps, SolverKind::kConjugateGradient);
  for (int m : {2, 4, 6, 8, 10, 12, 14})
    if (m <= max_level) bench_cantilever(m);
  return 0;
}
