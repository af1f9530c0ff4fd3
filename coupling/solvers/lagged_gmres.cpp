// The fast path's lagged solves (see coupled_solver.hpp): flexible GMRES on the whole of eq. (7)
// with the block lower triangle (or, weakly coupled, the block diagonal) of A's earlier factor and
// Ŝ's earlier preconditioner.
#include <tbb/task_group.h>

#include <algorithm>

#include "coupling/solvers/block_product.hpp"
#include "coupling/solvers/gmres.hpp"
#include "coupling/solvers/schur_state.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::coupling::detail {

bool SchurCGSolver::solve_lagged(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p,
                                 CoupledSolveReport& report, bool rebuild_preconditioner) {
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  Lag& lag = *lag_;
  Stopwatch clock;
  // A remesh changes P and H (the solid's A keeps its pattern): Ŝ's preconditioner is rebuilt
  // for the new pressure unknowns, A's factor is kept.
  if ((rebuild_preconditioner || !lag.P_pattern.matches(s.P) || !lag.H_pattern.matches(s.H)) &&
      !build_schur_preconditioner(s))
    return false;
  // Â⁻¹ is a preconditioner here: its factor in single precision reads half the bytes per solve
  // (unless a lagged solve with it missed its cap before: Lag::double_factor).
  const bool single = !lag.double_factor && factor_->cholesky.to_single_precision();
  report.solver = (lag.decoupled ? "block_diagonal_gmres+" : "block_gmres+") + lag.preconditioner_name;
  report.factor_age = lag.age + 1;
  report.setup_seconds += clock.lap();

  // Rows scaled by the block scales of residuals() at the initial guess, so that the single
  // residual norm GMRES minimizes weighs the solid row [N] and the fluid row [m³/s] alike.
  Eigen::VectorXd x(n + m);
  x.head(n) = u.size() == n ? u : Eigen::VectorXd::Zero(n);
  x.tail(m) = p.size() == m ? p : Eigen::VectorXd::Zero(m);
  auto positive = [](double v) { return v > 0 ? v : 1.0; };
  const double solid_scale =
      positive(std::max({s.b.norm(), (s.A * x.head(n)).norm(), (s.H.transpose() * x.tail(m)).norm()}));
  const double fluid_scale = positive(std::max({s.r.norm(), (s.H * x.head(n)).norm(), (s.P * x.tail(m)).norm()}));
  Eigen::VectorXd f(n + m);
  f << s.b / solid_scale, s.r / fluid_scale;

  // K x = [(A xᵤ − Hᵀ xₚ)/σₛ; (H xᵤ + P xₚ)/σ_f], the paper form of eq. (7) with scaled rows.
  const BlockProducts products(s);
  auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { products.apply(v, y, solid_scale, fluid_scale); };
  // z = P⁻¹ D⁻¹ v with P = [Â 0; H Ŝ]: zᵤ = Â⁻¹ σₛvᵤ, then zₚ = Ŝ⁻¹ (σ_f vₚ − H zᵤ). Decoupled
  // (Lag::decoupled: H zᵤ was a small part of σ_f vₚ in the last solve), P = diag(Â, Ŝ): zₚ =
  // Ŝ⁻¹ σ_f vₚ no longer waits for zᵤ, so the two run side by side (BoomerAMG is serial in
  // Debian's hypre). Either way ‖H zᵤ‖ / ‖σ_f vₚ‖ is measured for the next solve's choice.
  // Work vectors kept across the iterations (GMRES calls this once per iteration).
  Eigen::VectorXd zu(n), zp(m), flux(m), solid_rhs(n), fluid_rhs(m);
  const bool decoupled = lag.decoupled;
  double coupling_sum = 0;
  int coupling_count = 0;
  auto precondition = [&](const Eigen::VectorXd& v, Eigen::VectorXd& z) {
    z.resize(n + m);
    solid_rhs = solid_scale * v.head(n);
    fluid_rhs = fluid_scale * v.tail(m);
    if (decoupled) {
      tbb::task_group solid_solve;
      solid_solve.run([&] { factor_->cholesky.solve(solid_rhs, zu); });
      lag.precondition(fluid_rhs, zp);  // on the calling thread, the one MPI calls may come from
      solid_solve.wait();
    } else {
      factor_->cholesky.solve(solid_rhs, zu);
    }
    products.interface_flux(zu, flux);
    const double fluid_norm = fluid_rhs.norm();
    if (fluid_norm > 0) coupling_sum += flux.norm() / fluid_norm, ++coupling_count;
    if (!decoupled) {
      fluid_rhs -= flux;
      lag.precondition(fluid_rhs, zp);
    }
    z.head(n) = zu;
    z.tail(m) = zp;
  };

  // Each block's relative residual is at most the scaled norm, so stop at half the tolerance and
  // confirm from scratch; tighten tenfold if the scales at the guess were too loose.
  const int cap = std::min(options_.max_iterations, 3 * lag.fresh_iterations + 20);
  const bool converged = tighten_until_done(
      0.5 * options_.tolerance,
      [&](double target) {
        if (report.iterations >= cap) return false;
        const GmresResult g = right_preconditioned_gmres(apply, precondition, f, x, target, cap - report.iterations);
        report.iterations += g.iterations;
        if (!x.allFinite()) return false;
        report.residual = residuals(s, x.head(n), x.tail(m));
        return true;
      },
      [&] { return report.residual.max() <= options_.tolerance; });
  report.solve_seconds = clock.lap();
  lag.coupling_share = coupling_count > 0 ? coupling_sum / coupling_count : 0.0;
  // A missed cap never repeats the same choice: the block triangle, and the factor in double.
  lag.decoupled = converged && lag.coupling_share < Lag::kDecoupledBelow;
  if (!converged && single) lag.double_factor = true;
  if (!converged) return false;
  u = x.head(n);
  p = x.tail(m);
  ++lag.age;
  // Rebuild once the iterations the lagged blocks cost beyond a fresh solve's add up to twice a
  // fresh solve's: the rent-or-buy rule with a fresh set-up costing about two solves (measured:
  // 0.45 s set-up vs 0.25 s for 15 iterations at 40³ in bench_coupling, 0.08 s vs 0.05 s on the
  // flagship). Counted in iterations, not seconds, so that runs stay deterministic.
  const int extra = std::max(0, report.iterations - lag.fresh_iterations);
  lag.extra_iterations += extra;
  lag.factor_extra_iterations += extra;
  if (lag.extra_iterations >= 2 * std::max(lag.fresh_iterations, 1)) lag.refresh = true;
  return true;
}

}  // namespace tetfsi::coupling::detail
