// The fast path for eq. (7): CG on the SPD pressure Schur complement (see coupled_solver.hpp);
// from the second solve on, GMRES with the lagged blocks (lagged_gmres.cpp).
#include <algorithm>
#include <stdexcept>

#include "coupling/solvers/schur_state.hpp"
#include "support/conjugate_gradient.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::coupling::detail {

SchurCGSolver::SchurCGSolver(CoupledSolverOptions o)
    : options_(std::move(o)),
      factor_(std::make_unique<Factor>()),
      lag_(std::make_unique<Lag>()) {}
SchurCGSolver::~SchurCGSolver() = default;

void SchurCGSolver::request_fresh_solve() { lag_->refresh = true; }

bool SchurCGSolver::refactor(const SparseMatrix& A) {
  // A failed factorization is rare (a pre-stressed light solid: the bar scene) and a second
  // numeric factor is large (126 MB at 962k fluid tets on the flagship), so the factor is
  // overwritten and, on failure, recomputed from the earlier A rather than kept beside the new one.
  SparseMatrix earlier;
  const bool had_factor = factor_->valid;
  if (had_factor) earlier.swap(factor_->matrix);
  if (factor_->factorize(A)) return true;
  if (had_factor && !factor_->factorize(earlier))
    throw std::logic_error("schur_cg: the solid block's earlier factorization failed when repeated");
  return false;
}

bool SchurCGSolver::set_up_preconditioner() {
  Lag& lag = *lag_;
  bool ok = true;
  if (options_.preconditioner_apply) {
    if (options_.preconditioner_setup) options_.preconditioner_setup(lag.S_hat);
  } else {
    lag.ic.compute(lag.S_hat);
    ok = lag.ic.info() == Eigen::Success;
  }
  if (!options_.keep_checkpoint_state) lag.S_hat = SparseMatrix();  // the preconditioner holds its own copy
  return ok;
}

void SchurCGSolver::set_preconditioner() {
  Lag& lag = *lag_;
  if (options_.preconditioner_apply) {
    lag.precondition = options_.preconditioner_apply;
    lag.preconditioner_name = options_.preconditioner_name.empty() ? "custom" : options_.preconditioner_name;
  } else {
    lag.precondition = [&ic = lag.ic](const Eigen::VectorXd& r, Eigen::VectorXd& z) { z = ic.solve(r); };
    lag.preconditioner_name = "ic";
  }
}

bool SchurCGSolver::build_schur_preconditioner(const CoupledSystem& s) {
  Lag& lag = *lag_;
  lag.precondition = nullptr;
  lag.P_pattern.assign(SparseMatrix());
  lag.H_pattern.assign(SparseMatrix());
  if (s.num_pressures() > 0) {
    lag.S_hat = approximate_schur_complement(s);
    if (!set_up_preconditioner()) return false;
  } else {
    lag.S_hat = SparseMatrix();
  }
  set_preconditioner();
  lag.P_pattern.assign(s.P);
  lag.H_pattern.assign(s.H);
  return true;
}

CoupledSolveReport SchurCGSolver::solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) {
  s.check_sizes();
  const int n = s.num_solid_dofs();
  const bool can_lag = options_.reuse_factorization && n > 0 && s.num_pressures() > 0 && factor_->valid &&
                       factor_->pattern.matches(s.A) && lag_->precondition;
  CoupledSolveReport lagged;
  const bool lag_first = can_lag && !lag_->refresh;
  if (lag_first && lag_->factor_due()) {
    // A alone is refactorized; if it is not SPD the earlier factor stays (refactor() keeps it)
    // and the next attempt waits for another half solve's worth of extra iterations.
    Stopwatch factor_clock;
    if (refactor(s.A)) lag_->age = -1;  // factorized for this solve, which reports age 0
    lag_->factor_extra_iterations = 0;
    lagged.setup_seconds = factor_clock.lap();
  }
  if (lag_first && solve_lagged(s, u, p, lagged)) return lagged;
  Stopwatch factor_clock;
  const bool factored = n == 0 || refactor(s.A);
  const double factor_seconds = factor_clock.lap();
  if (factored) {
    // A fresh solve: nothing to lag, a rebuild was due, or GMRES missed its cap (the lagged blocks
    // were too far from this system; the report counts the lagged iterations and time too).
    CoupledSolveReport fresh = solve_fresh(s, u, p);
    fresh.iterations += lagged.iterations;
    fresh.setup_seconds += factor_seconds + lagged.setup_seconds;
    fresh.solve_seconds += lagged.solve_seconds;
    return fresh;
  }
  // A is not positive definite: the Schur complement P + H A⁻¹ Hᵀ is then not SPD and CG is not
  // defined, but GMRES on the whole system, preconditioned with the factor of an earlier SPD A,
  // still is (a light pre-stressed solid whose geometric stiffness outweighs M/h: the bar scene).
  // If the rebuild was due, Ŝ's preconditioner is rebuilt all the same, and the next attempt to
  // refactorize waits until the extra iterations have again added up to two fresh solves.
  if (can_lag && !lag_first) {
    lag_->refresh = false;
    lag_->extra_iterations = 0;
    lag_->factor_extra_iterations = 0;
    if (solve_lagged(s, u, p, lagged, /*rebuild_preconditioner=*/true)) {
      lagged.setup_seconds += factor_seconds;
      return lagged;
    }
  }
  throw CoupledSolveError(
      "schur_cg: the solid block A = M/h + C + (h/2)K' is not positive definite, so its Cholesky factorization "
      "failed: the solid's tangent stiffness K' lost definiteness (strong compression or pre-stress) by more than "
      "M/h makes up for" +
      std::string(can_lag ? ", and GMRES preconditioned with the factor of an earlier step did not converge" : "") +
      ". Take a smaller time step (simulation.dt), or use coupling.solver umfpack, which does not need A to be definite");
}

CoupledSolveReport SchurCGSolver::solve_fresh(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) {
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  CoupledSolveReport report;
  Stopwatch clock;

  // factor_ holds the Cholesky factor of this A (refactor()), reused by every CG iteration (two
  // triangular solves each) and by the lagged solves that follow.
  auto A_inv = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    Eigen::VectorXd y;
    if (n > 0) factor_->cholesky.solve(x, y);
    return y;
  };

  // Until this solve succeeds the lagged state is marked unusable (refresh), so that a caller
  // catching an exception never lags on blocks of a failed solve.
  Lag& lag = *lag_;
  lag.refresh = true;
  if (!build_schur_preconditioner(s))
    throw CoupledSolveError("schur_cg: incomplete Cholesky of the Schur approximation failed");
  report.solver = "schur_cg+" + lag.preconditioner_name;
  report.setup_seconds = clock.lap();

  auto apply_S = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    Eigen::VectorXd y = s.P * x;
    if (n > 0) y += s.H * A_inv(s.H.transpose() * x);
    return y;
  };
  auto recover_u = [&] { u = n > 0 ? A_inv(s.b + s.H.transpose() * p) : Eigen::VectorXd(); };

  // Preconditioned conjugate gradients (support/conjugate_gradient.hpp) on S. With
  // u = A⁻¹(b + Hᵀp) the solid row holds to round-off and the CG residual r − H A⁻¹ b − S p is the
  // fluid row's residual, so CG stops once it is below half the tolerance relative to the
  // fluid row's scale. The recursively updated residual drifts from the true one when A is stiff
  // (each S product goes through A⁻¹), so the block residuals of (u, p) are then computed from
  // scratch; if they miss the tolerance CG restarts from the current iterate with a 10x tighter
  // target (residual replacement).
  const Eigen::VectorXd rhs = n > 0 ? Eigen::VectorXd(s.r - s.H * A_inv(s.b)) : s.r;
  if (p.size() != m) p = Eigen::VectorXd::Zero(m);
  const double scale = std::max(s.r.norm(), rhs.norm());
  int it = 0;
  auto cg_pass = [&](double target) {
    Eigen::VectorXd res = rhs - apply_S(p);
    if (m > 0)
      it += preconditioned_cg([&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y = apply_S(v); }, lag.precondition,
                              res, p, target, options_.max_iterations - it);
    recover_u();
    if (!u.allFinite() || !p.allFinite()) return false;
    report.residual = residuals(s, u, p);
    return true;
  };
  tighten_until_done(0.5 * options_.tolerance * (scale > 0 ? scale : 1.0), cg_pass,
                     [&] { return report.residual.max() <= options_.tolerance || it >= options_.max_iterations; });
  report.iterations = it;
  report.solve_seconds = clock.lap();
  if (!u.allFinite() || !p.allFinite()) throw CoupledSolveError("schur_cg: non-finite iterate");
  require_converged(report, options_.tolerance);
  // From now on Â only preconditions the lagged solves (lagged_gmres.cpp), if there are any.
  if (n > 0 && options_.reuse_factorization && !lag.double_factor) factor_->cholesky.to_single_precision();
  lag.fresh_iterations = it;
  lag.age = 0;
  lag.extra_iterations = 0;
  lag.factor_extra_iterations = 0;
  lag.refresh = false;
  return report;
}

}  // namespace tetfsi::coupling::detail
