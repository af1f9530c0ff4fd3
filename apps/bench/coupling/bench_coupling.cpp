// Benchmark of the simultaneous coupling (issue 6), printing the common table:
//  1. piston (benchmarks.md §6): frequency error vs the exact added-mass frequency, by resolution;
//  2. one coupled step of a soft block in a fluid box (structured mesh), each solver of eq. (7)
//     against a fluid-only projection on the same mesh: cost of coupling and of each solver;
//  3. time splitting vs simultaneous on the piston at m_a/m_s = 2.5: largest stable step of each.
// Usage: bench_coupling [max_cells_per_side]   (default 32; 40 gives ~100k pressure unknowns)
#include <cstdio>
#include <cstdlib>

#include "apps/bench/bench_support.hpp"
#include "coupling/coupled_stepper.hpp"
#include "fluid/fluid_solver.hpp"
#include "mesh/structured_box.hpp"
#include "tests/coupling/piston_fixture.hpp"
#include "tests/coupling/sphere_fixture.hpp"

using namespace tetfsi;

namespace {

double piston_frequency(const test::PistonSetup& s, double periods) {
  auto stepper = test::make_piston(s, 1e-3);
  const int steps = static_cast<int>(periods / (s.exact_frequency() * s.time_step));
  double prev = 0, first = -1, last = -1;
  int n = 0;
  for (int k = 0; k < steps; ++k) {
    stepper->step();
    const double x = test::plug_displacement(*stepper);
    if (k > 0 && prev < 0 && x >= 0) {
      const double t = stepper->time() - s.time_step * x / (x - prev);
      if (first < 0) first = t;
      last = t, ++n;
    }
    prev = x;
  }
  return n >= 2 ? (n - 1) / (last - first) : 0.0;
}

/// A cube of fluid [0,1]³ with a soft solid block in its middle third; open top.
mesh::TetMesh block_in_box(int cells) {
  mesh::TetMesh m = mesh::structured_box({0, 0, 0}, {1, 1, 1}, cells, cells, cells);
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : m.tets[t]) c += m.vertices[v] / 4;
    const bool inside = (c.array() > 1.0 / 3).all() && (c.array() < 2.0 / 3).all();
    m.subdomain[t] = inside ? mesh::solid_subdomain(0) : mesh::kFluidSubdomain;
  }
  return m;
}

std::unique_ptr<coupling::CoupledStepper> make_block_scene(const mesh::TetMesh& m, coupling::CoupledSolverKind kind) {
  fluid::FluidParams fp;
  fp.density = 1000;
  solid::TetMaterial mat;
  mat.density = 500;  // light solid in heavy fluid
  mat.youngs_modulus = 1e5;
  mat.poisson_ratio = 0.3;
  coupling::CoupledSettings cs;
  cs.time_step = 1.0 / 60;
  cs.solver = kind;
  cs.solver_options.tolerance = 1e-8;
  cs.solid_gravity = {0, 0, -9.81};
  auto s = std::make_unique<coupling::CoupledStepper>(m, fp, std::vector<solid::TetMaterial>{mat}, cs);
  fluid::BoundaryPatch open;
  open.kind = fluid::FaceKind::kOpen;
  open.region.lo = {-1, -1, 1 - 1e-9};
  open.region.hi = {2, 2, 1 + 1e-9};
  s->fluid_boundary().patches.push_back(open);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  const int max_cells = argc > 1 ? std::atoi(argv[1]) : 32;
  bench::print_header();

  for (int cpm : {10, 20, 40}) {
    test::PistonSetup s;
    s.cells_per_metre = cpm;
    bench::Stopwatch clock;
    const double f = piston_frequency(s, 3.0);
    bench::print_row("piston m_a/m_s=10 (simultaneous, schur_cg)", std::to_string(cpm) + " cells/m, h=1/200",
                     fmt::format("{:.2e} rel. (frequency)", f / s.exact_frequency() - 1), clock.seconds());
  }

  for (double edge : {0.025, 0.015, 0.01}) {
    bench::Stopwatch clock;
    const test::SphereRun run = test::run_sphere(edge, 0.15, 2.6);
    bench::print_row("sphere on springs, added mass (simultaneous)",
                     fmt::format("edge {} m at the sphere, {} tets", edge, run.tets),
                     fmt::format("{:.2e} rel. (frequency)", run.frequency / run.exact - 1), clock.seconds());
  }

  for (int cells = 16; cells <= max_cells; cells += 8) {
    const mesh::TetMesh m = block_in_box(cells);
    const std::string res = fmt::format("{}³ cells, {} tets", cells, m.num_tets());
    {
      // Fluid-only projection on the same mesh: the solid treated as a fixed obstacle.
      fluid::FluidParams fp;
      fp.density = 1000;
      fluid::FluidSolver fs(fp);
      fs.initialize(m);
      fluid::BoundaryConditions bc;
      fluid::BoundaryPatch open;
      open.kind = fluid::FaceKind::kOpen;
      open.region.lo = {-1, -1, 1 - 1e-9};
      open.region.hi = {2, 2, 1 + 1e-9};
      bc.patches.push_back(open);
      fs.step(m, bc, 1.0 / 60);  // warm-up (MPI/hypre start-up)
      bench::Stopwatch clock;
      const auto rep = fs.step(m, bc, 1.0 / 60);
      bench::print_row("fluid-only step (advect+project, amg)", res,
                       fmt::format("div {:.1e} 1/s, solve {:.3f} s, {} unknowns", rep.max_divergence,
                                   rep.solve_seconds, rep.unknowns),
                       clock.seconds());
    }
    for (auto kind : {coupling::CoupledSolverKind::SchurCG, coupling::CoupledSolverKind::BiCGSTAB,
                      coupling::CoupledSolverKind::Umfpack}) {
      if (kind == coupling::CoupledSolverKind::Umfpack && cells > 24) continue;  // minutes and GBs beyond
      auto scene = make_block_scene(m, kind);
      bench::Stopwatch clock;
      const auto rep = scene->step();
      bench::print_row(fmt::format("coupled step, {}", rep.solve.solver), res,
                       fmt::format("residual {:.1e}, {} it, solve {:.3f} s, {}+{} unknowns", rep.solve.residual.max(),
                                   rep.solve.iterations, rep.solve.setup_seconds + rep.solve.solve_seconds,
                                   rep.pressure_unknowns, rep.solid_dofs),
                       clock.seconds());
    }
  }

  // Largest stable step of time splitting at m_a/m_s = 2.5 (none expected: §6 says unstable for
  // any h) against the simultaneous scheme at the same steps.
  for (double h : {1.0 / 30, 1.0 / 120, 1.0 / 480}) {
    for (auto scheme : {coupling::CouplingScheme::kSimultaneous, coupling::CouplingScheme::kTimeSplitting}) {
      test::PistonSetup s;
      s.fluid_density = 250;
      s.time_step = h;
      s.scheme = scheme;
      bench::Stopwatch clock;
      std::string verdict;
      try {
        const double f = piston_frequency(s, 3.0);
        verdict = f > 0 ? fmt::format("{:.2e} rel. (frequency)", f / s.exact_frequency() - 1) : "no oscillation";
      } catch (const std::exception& e) {
        verdict = "diverged (detected)";
      }
      bench::print_row(scheme == coupling::CouplingScheme::kSimultaneous ? "piston m_a/m_s=2.5 simultaneous"
                                                                          : "piston m_a/m_s=2.5 time splitting",
                       fmt::format("h=1/{:.0f}", 1 / h), verdict, clock.seconds());
    }
  }
  return 0;
}
