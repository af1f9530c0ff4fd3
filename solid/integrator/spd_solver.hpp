#pragma once
/// @file spd_solver.hpp
/// Sparse symmetric positive definite solver for the solid system A u = b: CHOLMOD supernodal
/// Cholesky (SuiteSparse through Eigen's CholmodSupport; the symbolic analysis is reused while
/// the pattern stays the same) or Eigen's conjugate gradient with an incomplete Cholesky
/// preconditioner (warm-started). Records the time and iterations of the last solve.
#include <Eigen/SparseCore>
#include <memory>
#include <string>

namespace tetfsi::solid {

enum class SolverKind { kCholmod, kConjugateGradient };

/// Parses "cholmod" or "cg". @throws SolidError otherwise.
SolverKind parse_solver_kind(const std::string& name);

struct SolveStats {
  double seconds = 0;     ///< wall time of factorization + solve [s]
  int iterations = 1;     ///< CG iterations (1 for a direct solve)
  double residual = 0;    ///< CG: estimated relative residual; direct: 0
};

/// Limits the threads of the BLAS under CHOLMOD's supernodal factorization (OpenBLAS only;
/// found at run time, no-op otherwise). On a small shared machine a multi-threaded BLAS that
/// busy-waits costs more than it gains (measured: 10k-tet step 248 ms -> 68 ms with 1 thread).
/// @return true if an OpenBLAS was found
bool limit_blas_threads(int threads);

class SpdSolver {
 public:
  explicit SpdSolver(SolverKind kind = SolverKind::kCholmod, double cg_tolerance = 1e-10, int cg_max_iterations = 2000);
  ~SpdSolver();
  SpdSolver(SpdSolver&&) noexcept;
  SpdSolver& operator=(SpdSolver&&) noexcept;

  /// Solves A x = b; `x` is the initial guess for CG. A must be symmetric (both triangles).
  /// @throws SolidError if A is not positive definite (CHOLMOD) or CG does not converge;
  ///         `context` is prefixed to the message (e.g. "step 12").
  void solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
             const std::string& context = {});

  const SolveStats& last_stats() const { return stats_; }
  SolverKind kind() const { return kind_; }

 private:
  struct Impl;
  SolverKind kind_;
  double cg_tolerance_;
  int cg_max_iterations_;
  std::unique_ptr<Impl> impl_;
  SolveStats stats_;
};

}  // namespace tetfsi::solid
