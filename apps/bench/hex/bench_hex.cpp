// bench_hex: Total Lagrangian hex8 (solid/hex) performance and accuracy.
//  1. Newton iterations per load step and seconds per iteration (assembly + linear solve) for a
//     neo-Hookean cube compressed by 20 % in 2 load steps, at ~1k, ~10k, ~50k hexes;
//  2. TBB assembly speed-up (F_int + K_T) on 1 vs 2 threads at the largest size;
//  3. the cantilever roll-up (Euler-Bernoulli elastica, curvature M / (EI); M = 2 pi EI / L as a prescribed end rotation
//     of 2 pi) at the benchmark resolution: tip-root gap, worst tip error along the path, moment error.
// Usage: bench_hex [--max-cells N] [--direct-10k] [--assembly-only] [--rollup-only] [--out DIR]
//   --direct-10k: also the ~10k case with CHOLMOD (minutes: ~23 GFlop per factorisation);
//   DIR: write the rolled-up cantilever as .vtu.
// Linear solver: CHOLMOD (exact, robust to indefinite K_T via LDLT) where a direct factorisation is
// affordable; Eigen Jacobi-preconditioned CG for the larger 3D blocks, whose direct factorisation
// costs ~ dofs^2 flops.
#include <fmt/core.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "apps/bench/bench_support.hpp"
#include "solid/hex/block_mesh.hpp"
#include "solid/hex/hex_output.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/hex_model.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::hex;
namespace bench = tetfsi::bench;

namespace {

void compression_case(int n, LinearSolverKind solver) {
  const auto mesh = block_mesh({0, 0, 0}, {1, 1, 1}, n, n, n);
  Material m;
  m.law = MaterialLaw::kNeoHookeanBonetWood;
  m.youngs_modulus = 1e6;
  m.poisson_ratio = 0.3;
  BoundaryConditions bc;
  fix_component(bc, nodes_in_box(mesh, {-1, -1, 0}, {2, 2, 0}), 2);
  fix_component(bc, {0}, 0);
  fix_component(bc, {0}, 1);
  fix_component(bc, {n}, 1);
  for (int v : nodes_in_box(mesh, {-1, -1, 1}, {2, 2, 1})) bc.prescribed.emplace_back(3 * v + 2, -0.2);
  bench::Stopwatch watch;
  const HexModel model(mesh, m, Hex8Formulation::Standard);  // the element of the table in solid/hex/README.md
  StaticOptions opt;
  opt.load_steps = 2;
  opt.linear_solver = solver;
  const auto r = solve_static(model, bc, opt);
  const double wall = watch.seconds();
  std::string its;
  for (const auto& s : r.steps) its += (its.empty() ? "" : "/") + std::to_string(s.iterations);
  // Exact: homogeneous uniaxial state, so the top's z-displacement is -0.2 and sigma_xx = 0;
  // report the largest lateral Cauchy stress relative to the axial one as the error.
  std::vector<double> cauchy, pk2;
  model.element_stresses(r.displacement, cauchy, pk2);
  double lateral = 0, axial = 0;
  for (int e = 0; e < mesh.num_hexes(); ++e) {
    lateral = std::max({lateral, std::abs(cauchy[6 * e]), std::abs(cauchy[6 * e + 1])});
    axial = std::max(axial, std::abs(cauchy[6 * e + 2]));
  }
  const bool cg = solver == LinearSolverKind::ConjugateGradient;
  bench::print_row(fmt::format("compression 20%, NH, {}; Newton its/step {}; s/it {:.3f} (assembly {:.3f} + solve {:.3f})",
                               cg ? fmt::format("Jacobi-CG ({} CG its/solve)", r.cg_iterations / r.total_iterations) : "CHOLMOD",
                               its, (r.assembly_seconds + r.solve_seconds) / r.total_iterations,
                               r.assembly_seconds / r.total_iterations, r.solve_seconds / r.total_iterations),
                   fmt::format("{}^3 = {} hexes, {} dofs", n, mesh.num_hexes(), 3 * mesh.num_vertices()),
                   fmt::format("{:.1e} (max |sigma_lat| / |sigma_zz|, exact 0)", lateral / axial), wall);
}

void assembly_speedup(int n) {
  const auto mesh = block_mesh({0, 0, 0}, {1, 1, 1}, n, n, n);
  Material m;
  m.law = MaterialLaw::kNeoHookeanBonetWood;
  const HexModel model(mesh, m, Hex8Formulation::Standard);  // the element of the table in solid/hex/README.md
  Eigen::VectorXd d(3 * model.num_nodes());
  for (int i = 0; i < model.num_nodes(); ++i) d.segment<3>(3 * i) = 0.1 * mesh.vertices[i].array().square().matrix();
  Eigen::VectorXd f;
  tetfsi::solid::SparseMatrix K;
  double t[2] = {0, 0};
  Eigen::VectorXd f1;
  for (int threads = 1; threads <= 2; ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    model.evaluate(d, f, &K);  // warm-up
    bench::Stopwatch w;
    const int reps = 3;
    for (int k = 0; k < reps; ++k) model.evaluate(d, f, &K);
    t[threads - 1] = w.seconds() / reps;
    if (threads == 1) f1 = f;
  }
  const double diff = (f - f1).cwiseAbs().maxCoeff();
  bench::print_row(fmt::format("assembly F_int + K_T: 1 thread {:.3f} s, 2 threads {:.3f} s, speed-up {:.2f} ({} colours)",
                               t[0], t[1], t[0] / t[1], model.num_colors()),
                   fmt::format("{}^3 = {} hexes", n, mesh.num_hexes()),
                   fmt::format("{:.0e} (max |F_int(2 thr) - F_int(1 thr)|, deterministic)", diff), t[0] + t[1]);
}

void rollup_case(int nx, int ny, int nz, const std::string& out, double slenderness = 20) {
  const double L = 1, h = L / slenderness, b = h;
  Material m;
  m.law = MaterialLaw::kStVK;
  m.youngs_modulus = 1e7;
  m.poisson_ratio = 0.0;
  const double EI = m.youngs_modulus * b * h * h * h / 12;
  const auto mesh = block_mesh({0, 0, 0}, {L, h, b}, nx, ny, nz);
  BoundaryConditions bc;
  fix_nodes(bc, nodes_in_box(mesh, {0, 0, 0}, {0, h, b}));
  RotatingFace face;
  face.nodes = nodes_in_box(mesh, {L, 0, 0}, {L, h, b});
  face.center = {L, h / 2, b / 2};
  face.axis = Eigen::Vector3d::UnitZ();
  face.angle = 2 * M_PI;
  bc.rotating_faces.push_back(face);
  auto tip = [&](const Eigen::VectorXd& u) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : face.nodes) c += mesh.vertices[v] + u.segment<3>(3 * v);
    return Eigen::Vector3d(c / static_cast<double>(face.nodes.size()));
  };
  bench::Stopwatch watch;
  const HexModel model(mesh, m, Hex8Formulation::Standard);  // the element of the table in solid/hex/README.md
  StaticOptions opt;
  opt.load_steps = 16;
  double worst_tip = 0, worst_moment = 0;
  const auto r = solve_static(model, bc, opt, 1.0, [&](const StepLog& s, const Eigen::VectorXd& u) {
    const double theta = s.load_factor * 2 * M_PI;
    const Eigen::Vector3d exact(L * std::sin(theta) / theta, h / 2 + L * (1 - std::cos(theta)) / theta, b / 2);
    worst_tip = std::max(worst_tip, (tip(u) - exact).norm() / L);
    Eigen::Vector3d F, M;
    face_reaction(model, face, u, F, M);
    worst_moment = std::max(worst_moment, std::abs(M.z() - EI * theta / L) / (EI * theta / L));
  });
  const double wall = watch.seconds();
  const double gap = (tip(r.displacement) - Eigen::Vector3d(0, h / 2, b / 2)).norm() / L;
  const double moment_err = (r.face_moments[0].z() - 2 * M_PI * EI / L) / (2 * M_PI * EI / L);
  bench::print_row(fmt::format("cantilever roll-up L/h={:.0f}, 16 steps, {} Newton its", slenderness, r.total_iterations),
                   fmt::format("{}x{}x{} hexes (dx/h = {:.2f})", nx, ny, nz, L / nx / h),
                   fmt::format("tip-root gap {:.1e} L; worst tip err {:.1e} L; M(2pi) err {:+.1e}, worst {:.1e}", gap,
                               worst_tip, moment_err, worst_moment),
                   wall);
  if (!out.empty()) {
    std::filesystem::create_directories(out);
    write_hex_vtu(std::filesystem::path(out) / fmt::format("cantilever_rollup_{}x{}x{}.vtu", nx, ny, nz), model,
                  r.displacement);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int max_cells = 60000;
  std::string out;
  bool direct_10k = false, assembly_only = false, rollup_only = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--max-cells") && i + 1 < argc) {
      max_cells = std::stoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--rollup-only")) {
      rollup_only = true;
    } else if (!std::strcmp(argv[i], "--assembly-only")) {
      assembly_only = true;
    } else if (!std::strcmp(argv[i], "--direct-10k")) {
      direct_10k = true;
    } else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) {
      out = argv[++i];
    } else {
      fmt::print(stderr, "usage: bench_hex [--max-cells N] [--direct-10k] [--assembly-only] [--rollup-only] [--out DIR]\n");
      return 2;
    }
  }
  try {
    bench::print_header();
    const int big = std::cbrt(static_cast<double>(max_cells)) >= 37 ? 37 : 22;
    if (assembly_only) {
      assembly_speedup(big);
      return 0;
    }
    rollup_case(100, 2, 1, out);
    rollup_case(200, 4, 2, out);
    // Slender beam: fibre strains pi h / L = 3 % instead of 16 %, so the St. Venant-Kirchhoff
    // departure from the linear moment-curvature law of the elastica shrinks ~25-fold.
    rollup_case(1000, 2, 1, out, 100);
    if (rollup_only) return 0;
    assembly_speedup(big);
    compression_case(10, LinearSolverKind::Cholmod);
    if (direct_10k) compression_case(22, LinearSolverKind::Cholmod);
    for (int n : {10, 22, 37}) {
      if (n * n * n <= max_cells) compression_case(n, LinearSolverKind::ConjugateGradient);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_hex: {}\n", e.what());
    return 1;
  }
  return 0;
}
