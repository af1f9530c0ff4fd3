// The fast path for eq. (7): CG on the SPD pressure Schur complement (see coupled_solver.hpp).
#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>

#include "coupling/solvers/solver_impls.hpp"
#include "coupling/solvers/stopwatch.hpp"

namespace tetfsi::coupling::detail {

CoupledSolveReport SchurCGSolver::solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) {
  s.check_sizes();
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  CoupledSolveReport report;
  Stopwatch clock;

  // A = M/h + C + (h/2)K' is SPD for a stable step: one supernodal Cholesky per step, reused by
  // every CG iteration (two triangular solves each).
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> chol_A;
  if (n > 0) {
    chol_A.compute(s.A);
    if (chol_A.info() != Eigen::Success)
      throw CoupledSolveError("schur_cg: Cholesky of the solid block A failed (A not positive definite: "
                              "time step too large for the linearized stiffness?)");
  }
  auto A_inv = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    return n > 0 ? Eigen::VectorXd(chol_A.solve(x)) : Eigen::VectorXd();
  };

  // Preconditioner for S = C + H A⁻¹ Hᵀ: the caller's (e.g. BoomerAMG) or IC of Ŝ.
  const SparseMatrix S_hat = approximate_schur_complement(s);
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>> ic;
  std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> precondition;
  if (options_.preconditioner_apply) {
    if (options_.preconditioner_setup && m > 0) options_.preconditioner_setup(S_hat);
    precondition = options_.preconditioner_apply;
    report.solver = "schur_cg+" + (options_.preconditioner_name.empty() ? "custom" : options_.preconditioner_name);
  } else {
    if (m > 0) {
      ic.compute(S_hat);
      if (ic.info() != Eigen::Success) throw CoupledSolveError("schur_cg: incomplete Cholesky of the Schur approximation failed");
    }
    precondition = [&](const Eigen::VectorXd& r, Eigen::VectorXd& z) { z = ic.solve(r); };
    report.solver = "schur_cg+ic";
  }
  report.setup_seconds = clock.lap();

  auto apply_S = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    Eigen::VectorXd y = s.C * x;
    if (n > 0) y += s.H * A_inv(s.H.transpose() * x);
    return y;
  };

  // Preconditioned conjugate gradients (Saad, "Iterative Methods for Sparse Linear Systems",
  // Alg. 9.1). Written out because S is only available as an operator; Eigen's
  // ConjugateGradient would need a matrix-free wrapper with its expression traits, which is longer.
  // The recursively updated residual drifts from the true one when A is stiff (each S product
  // goes through A⁻¹), so convergence is confirmed on the true residual, restarting CG from the
  // current iterate if needed (residual replacement).
  const Eigen::VectorXd rhs = n > 0 ? Eigen::VectorXd(s.r - s.H * A_inv(s.b)) : s.r;
  if (p.size() != m) p = Eigen::VectorXd::Zero(m);
  const double rhs_norm = rhs.norm();
  const double target = 0.1 * options_.tolerance * (rhs_norm > 0 ? rhs_norm : 1.0);
  int it = 0;
  for (int restart = 0; restart < 5 && m > 0; ++restart) {
    Eigen::VectorXd res = rhs - apply_S(p), z(m), dir(m);
    if (res.norm() <= target) break;
    precondition(res, z);
    dir = z;
    double rz = res.dot(z);
    for (; it < options_.max_iterations; ++it) {
      const Eigen::VectorXd Sd = apply_S(dir);
      const double alpha = rz / dir.dot(Sd);
      p += alpha * dir;
      res -= alpha * Sd;
      if (res.norm() <= 0.1 * target) {
        ++it;
        break;
      }
      precondition(res, z);
      const double rz_next = res.dot(z);
      dir = z + (rz_next / rz) * dir;
      rz = rz_next;
    }
    if (it >= options_.max_iterations) break;
  }
  report.iterations = it;
  u = n > 0 ? A_inv(s.b + s.H.transpose() * p) : Eigen::VectorXd();
  report.solve_seconds = clock.lap();
  if (!u.allFinite() || !p.allFinite()) throw CoupledSolveError("schur_cg: non-finite iterate");
  report.residual = residuals(s, u, p);
  require_converged(report, options_.tolerance);
  return report;
}

}  // namespace tetfsi::coupling::detail
