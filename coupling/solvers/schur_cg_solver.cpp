// The fast path for eq. (7): CG on the SPD pressure Schur complement (see coupled_solver.hpp).
#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <vector>

#include "coupling/solvers/solver_impls.hpp"
#include "coupling/solvers/stopwatch.hpp"

namespace tetfsi::coupling::detail {

/// Supernodal Cholesky of A = M/h + C + (h/2)K′ (SPD for a stable step). The fill-reducing
/// ordering and symbolic factor (CHOLMOD's analysis) depend only on A's sparsity pattern, which
/// stays the same from step to step while the solid meshes do (the remesher freezes them), so
/// they are computed once and only the numeric factorization is redone per step.
struct SchurCGSolver::Factor {
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
  std::vector<SparseMatrix::StorageIndex> outer, inner;  // pattern the analysis was made for

  /// Factorizes A, re-analysing only when its pattern changed. Returns false if A is not SPD.
  bool factorize(const SparseMatrix& A) {
    const auto* o = A.outerIndexPtr();
    const auto* i = A.innerIndexPtr();
    const bool same = A.isCompressed() && outer.size() == static_cast<std::size_t>(A.outerSize() + 1) &&
                      inner.size() == static_cast<std::size_t>(A.nonZeros()) && std::equal(outer.begin(), outer.end(), o) &&
                      std::equal(inner.begin(), inner.end(), i);
    if (!same) {
      outer.clear(), inner.clear();
      llt.analyzePattern(A);
      if (A.isCompressed()) outer.assign(o, o + A.outerSize() + 1), inner.assign(i, i + A.nonZeros());
    }
    llt.factorize(A);
    return llt.info() == Eigen::Success;
  }
};

SchurCGSolver::SchurCGSolver(CoupledSolverOptions o) : options_(std::move(o)), factor_(std::make_unique<Factor>()) {}
SchurCGSolver::~SchurCGSolver() = default;

CoupledSolveReport SchurCGSolver::solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) {
  s.check_sizes();
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  CoupledSolveReport report;
  Stopwatch clock;

  // One numeric Cholesky of A per step, reused by every CG iteration (two triangular solves each).
  if (n > 0 && !factor_->factorize(s.A))
    throw CoupledSolveError("schur_cg: the solid block A = M/h + C + (h/2)K' is not positive definite, so its "
                            "Cholesky factorization failed: the solid's tangent stiffness K' lost definiteness "
                            "(strong compression or pre-stress) by more than M/h makes up for. Take a smaller dt, "
                            "or use coupling.solver umfpack, which does not need A to be definite");
  auto A_inv = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    return n > 0 ? Eigen::VectorXd(factor_->llt.solve(x)) : Eigen::VectorXd();
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
  auto recover_u = [&] { u = n > 0 ? A_inv(s.b + s.H.transpose() * p) : Eigen::VectorXd(); };

  // Preconditioned conjugate gradients (Saad, "Iterative Methods for Sparse Linear Systems",
  // Alg. 9.1). Written out because S is only available as an operator; Eigen's
  // ConjugateGradient would need a matrix-free wrapper with its expression traits, which is longer.
  // With u = A⁻¹(b + Hᵀp) the solid row holds to round-off and the CG residual r − H A⁻¹ b − S p
  // is the fluid row's residual, so CG stops once it is below half the tolerance relative to the
  // fluid row's scale. The recursively updated residual drifts from the true one when A is stiff
  // (each S product goes through A⁻¹), so the block residuals of (u, p) are then computed from
  // scratch; if they miss the tolerance CG restarts from the current iterate with a 10x tighter
  // target (residual replacement).
  const Eigen::VectorXd rhs = n > 0 ? Eigen::VectorXd(s.r - s.H * A_inv(s.b)) : s.r;
  if (p.size() != m) p = Eigen::VectorXd::Zero(m);
  const double scale = std::max(s.r.norm(), rhs.norm());
  double target = 0.5 * options_.tolerance * (scale > 0 ? scale : 1.0);
  int it = 0;
  for (int pass = 0; pass < 5; ++pass, target *= 0.1) {
    Eigen::VectorXd res = rhs - apply_S(p), z(m), dir(m);
    double rz_previous = 0;
    for (bool first = true; m > 0 && res.norm() > target && it < options_.max_iterations; ++it, first = false) {
      precondition(res, z);
      const double rz = res.dot(z);
      dir = first ? z : Eigen::VectorXd(z + (rz / rz_previous) * dir);
      rz_previous = rz;
      const Eigen::VectorXd Sd = apply_S(dir);
      const double alpha = rz / dir.dot(Sd);
      p += alpha * dir;
      res -= alpha * Sd;
    }
    recover_u();
    if (!u.allFinite() || !p.allFinite()) break;
    report.residual = residuals(s, u, p);
    if (report.residual.max() <= options_.tolerance || it >= options_.max_iterations) break;
  }
  report.iterations = it;
  report.solve_seconds = clock.lap();
  if (!u.allFinite() || !p.allFinite()) throw CoupledSolveError("schur_cg: non-finite iterate");
  require_converged(report, options_.tolerance);
  return report;
}

}  // namespace tetfsi::coupling::detail
