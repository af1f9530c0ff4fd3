// BiCGSTAB on the unsymmetric paper form of eq. (7), as Chentanez et al. 2006 solve it (§3.3).
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <memory>

#include "coupling/solvers/solver_impls.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::coupling::detail {
namespace {

using IncompleteCholesky = Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>>;

/// Block-diagonal preconditioner P = diag(IC(Ã), IC(Ŝ)) in the form Eigen's iterative solvers
/// expect (compute/solve/info). The factors are set up by `setup`, from the two SPD diagonal
/// blocks, before BiCGSTAB::compute; the paper's "incomplete Cholesky" applies to those blocks.
/// (NaturalOrdering: the dependency probe found it much better than Eigen's default AMD here.)
class BlockDiagonalIC {
 public:
  void setup(const SparseMatrix& A, const SparseMatrix& S) {
    n_ = static_cast<int>(A.rows());
    a_ = std::make_shared<IncompleteCholesky>(A);
    s_ = S.rows() > 0 ? std::make_shared<IncompleteCholesky>(S) : nullptr;
    ok_ = a_->info() == Eigen::Success && (!s_ || s_->info() == Eigen::Success);
  }
  template <class M> BlockDiagonalIC& analyzePattern(const M&) { return *this; }
  template <class M> BlockDiagonalIC& factorize(const M&) { return *this; }
  template <class M> BlockDiagonalIC& compute(const M&) { return *this; }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& r) const {
    Eigen::VectorXd z(r.size());
    if (n_ > 0) z.head(n_) = a_->solve(r.head(n_));
    if (s_) z.tail(r.size() - n_) = s_->solve(r.tail(r.size() - n_));
    return z;
  }
  Eigen::ComputationInfo info() const { return ok_ ? Eigen::Success : Eigen::NumericalIssue; }

 private:
  int n_ = 0;
  bool ok_ = false;
  std::shared_ptr<IncompleteCholesky> a_, s_;
};

SparseMatrix scaled(const SparseMatrix& M, const Eigen::VectorXd& d) {
  return SparseMatrix(d.asDiagonal() * M * d.asDiagonal());
}

}  // namespace

CoupledSolveReport BiCGSTABSolver::solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) {
  s.check_sizes();
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  CoupledSolveReport report;
  report.solver = "bicgstab+block_ic";
  Stopwatch clock;

  // Symmetric Jacobi scaling D^{-1/2} K D^{-1/2}: the two block rows carry different units
  // (forces and volume fluxes); scaling makes one relative tolerance meaningful for both.
  Eigen::VectorXd d(n + m);
  d << s.A.diagonal(), s.P.diagonal();
  for (int i = 0; i < d.size(); ++i) d[i] = d[i] > 0 ? 1.0 / std::sqrt(d[i]) : 1.0;
  const SparseMatrix K = scaled(paper_form_matrix(s), d);

  Eigen::BiCGSTAB<SparseMatrix, BlockDiagonalIC> bicg;
  bicg.preconditioner().setup(scaled(s.A, d.head(n)), scaled(approximate_schur_complement(s), d.tail(m)));
  if (bicg.preconditioner().info() != Eigen::Success)
    throw CoupledSolveError("bicgstab: incomplete Cholesky of a diagonal block failed");
  bicg.compute(K);
  report.setup_seconds = clock.lap();

  Eigen::VectorXd rhs(n + m), guess = Eigen::VectorXd::Zero(n + m);
  rhs << s.b, s.r;
  rhs = d.cwiseProduct(rhs);
  if (u.size() == n && p.size() == m) {
    guess << u, p;
    guess = guess.cwiseQuotient(d);
  }
  // BiCGSTAB stops on the residual of the scaled system as a whole; the block rows' residuals
  // (residuals(), relative to each row's own scale) can still miss the tolerance when one row is
  // much smaller than the other. Then it goes on from its iterate with a 10x tighter target.
  Eigen::VectorXd y = guess, x;
  int iterations = 0;
  auto pass = [&](double target) {
    bicg.setTolerance(target);
    bicg.setMaxIterations(std::max(1, options_.max_iterations - iterations));
    y = bicg.solveWithGuess(rhs, y);
    iterations += static_cast<int>(bicg.iterations());
    x = d.cwiseProduct(y);
    if (!x.allFinite()) return false;
    report.residual = residuals(s, x.head(n), x.tail(m));
    return true;
  };
  tighten_until_done(0.1 * options_.tolerance, pass, [&] {
    return report.residual.max() <= options_.tolerance || iterations >= options_.max_iterations;
  });
  report.solve_seconds = clock.lap();
  report.iterations = iterations;
  if (!x.allFinite()) throw CoupledSolveError("bicgstab: breakdown (non-finite iterate)");
  split_and_check(s, x, options_.tolerance, report, u, p);
  return report;
}

}  // namespace tetfsi::coupling::detail
