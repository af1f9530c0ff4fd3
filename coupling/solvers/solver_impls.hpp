#pragma once
/// @file solver_impls.hpp
/// Private: the three CoupledSolver implementations (see coupled_solver.hpp) and shared helpers.
#include <memory>

#include "coupling/solvers/coupled_solver.hpp"

namespace tetfsi::coupling::detail {

/// Ŝ = P + H diag(A)⁻¹ Hᵀ: a sparse SPD approximation of the Schur complement P + H A⁻¹ Hᵀ,
/// used to precondition the pressure block (Benzi, Golub & Liesen 2005, sec. 10.1).
SparseMatrix approximate_schur_complement(const CoupledSystem& system);

/// Throws CoupledSolveError if the residuals of (u, p) exceed the tolerance.
void require_converged(const CoupledSolveReport& report, double tolerance);

/// Residual replacement of the iterative solvers: an inner solve from the current iterate to a
/// target on its own (scaled or recursively updated) residual, then the true block residuals from
/// scratch; if they miss, again with a tenfold tighter target, at most five passes.
/// `pass(target)` runs one inner solve and returns false to stop (non-finite iterate, budget
/// spent); `done()` says whether the block residuals are good enough. Returns whether done().
template <class Pass, class Done>
bool tighten_until_done(double target, Pass&& pass, Done&& done) {
  for (int k = 0; k < 5; ++k, target *= 0.1) {
    if (!pass(target)) return false;
    if (done()) return true;
  }
  return false;
}

/// Splits the monolithic solution x = [u; p] (n + m), records its residuals in `report` and
/// checks them against `tolerance` (throws CoupledSolveError).
void split_and_check(const CoupledSystem& s, const Eigen::VectorXd& x, double tolerance, CoupledSolveReport& report,
                     Eigen::VectorXd& u, Eigen::VectorXd& p);

class UmfpackSolver final : public CoupledSolver {
 public:
  explicit UmfpackSolver(CoupledSolverOptions o) : options_(std::move(o)) {}
  CoupledSolveReport solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) override;

 private:
  CoupledSolverOptions options_;
};

class BiCGSTABSolver final : public CoupledSolver {
 public:
  explicit BiCGSTABSolver(CoupledSolverOptions o) : options_(std::move(o)) {}
  CoupledSolveReport solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) override;

 private:
  CoupledSolverOptions options_;
};

class SchurCGSolver final : public CoupledSolver {
 public:
  explicit SchurCGSolver(CoupledSolverOptions o);
  ~SchurCGSolver() override;
  CoupledSolveReport solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) override;
  void request_fresh_solve() override;
  void write_state(BinaryWriter& out) const override;
  void read_state(BinaryReader& in) override;

 private:
  struct Factor;  // CHOLMOD factor of A, its symbolic analysis kept while A's pattern stays
  struct Lag;     // what the lagged solves keep: Ŝ's pattern and preconditioner, iteration counts
  /// Factorizes A in place of the current factor; if A is not SPD, returns false and restores
  /// the current factor by factorizing its matrix again (the same bits: CHOLMOD is deterministic
  /// for a given matrix), so that one numeric factor is ever held.
  bool refactor(const SparseMatrix& A);
  /// Sets up Ŝ's preconditioner (the caller's or IC of Ŝ = P + H diag(A)⁻¹ Hᵀ) in lag_ and records
  /// the patterns of P and H it was built for; false if the incomplete Cholesky failed (lag_ is
  /// then left without a preconditioner).
  bool build_schur_preconditioner(const CoupledSystem& s);
  /// Sets up Ŝ's preconditioner (the caller's or IC) on lag_->S_hat; false if IC failed.
  bool set_up_preconditioner();
  /// Points lag_->precondition at the caller's preconditioner or lag_'s IC, and names it.
  void set_preconditioner();
  /// Fresh Schur-complement CG with factor_ (A's factor, or none for n = 0); sets up Ŝ's
  /// preconditioner for this system.
  CoupledSolveReport solve_fresh(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p);
  /// GMRES on the whole system with the lagged blocks (Ŝ's preconditioner rebuilt first if its
  /// pattern changed or `rebuild_preconditioner`); returns false (u, p untouched) if it did not
  /// converge within its iteration cap.
  bool solve_lagged(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p, CoupledSolveReport& report,
                    bool rebuild_preconditioner = false);
  CoupledSolverOptions options_;
  std::unique_ptr<Factor> factor_;  // the current factor of A
  std::unique_ptr<Lag> lag_;
};

}  // namespace tetfsi::coupling::detail
