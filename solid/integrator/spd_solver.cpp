#include "solid/integrator/spd_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>

#include <dlfcn.h>

#include "solid/solid_error.hpp"
#include "support/stopwatch.hpp"
#include "support/number_text.hpp"

namespace tetfsi::solid {

SolverKind parse_solver_kind(const std::string& name) {
  if (name == "cholmod") return SolverKind::kCholmod;
  if (name == "cg") return SolverKind::kConjugateGradient;
  if (name == "cg_ic") return SolverKind::kConjugateGradientIC;
  throw SolidError("unknown solid solver '" + name + "' (expected \"cholmod\", \"cg\" or \"cg_ic\")");
}

bool limit_blas_threads(int threads) {
  using SetThreads = void (*)(int);
  auto* set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return false;
  set(threads);
  return true;
}

struct SpdSolver::Impl {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholmod;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                           Eigen::IncompleteCholesky<double>>
      cg_ic;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg_jacobi;
  Eigen::Index analyzed_rows = -1, analyzed_nnz = -1;
};

SpdSolver::SpdSolver(SolverKind kind, double cg_tolerance, int cg_max_iterations)
    : kind_(kind), cg_tolerance_(cg_tolerance), cg_max_iterations_(cg_max_iterations), impl_(std::make_unique<Impl>()) {}
SpdSolver::~SpdSolver() = default;
SpdSolver::SpdSolver(SpdSolver&&) noexcept = default;
SpdSolver& SpdSolver::operator=(SpdSolver&&) noexcept = default;

template <class Solver>
void SpdSolver::run_cg(Solver& cg, const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                       bool reanalyze, const std::string& where) {
  cg.setTolerance(cg_tolerance_);
  cg.setMaxIterations(cg_max_iterations_);
  if (reanalyze) cg.analyzePattern(A);
  cg.factorize(A);
  if (cg.info() != Eigen::Success) throw SolidError(where + "CG preconditioner set-up failed");
  if (x.size() != b.size()) x.setZero(b.size());
  x = cg.solveWithGuess(b, x);
  stats_.iterations = static_cast<int>(cg.iterations());
  stats_.residual = cg.error();
  if (cg.info() != Eigen::Success)
    throw SolidError(where + "conjugate gradient did not converge in " + std::to_string(cg_max_iterations_) +
                     " iterations (relative residual " + number_text(stats_.residual) + ")");
}

void SpdSolver::solve(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                      const std::string& context) {
  const Stopwatch clock;
  const std::string where = context.empty() ? std::string() : context + ": ";
  if (A.rows() != A.cols() || A.rows() != b.size()) throw SolidError(where + "solid system has inconsistent sizes");
  // The pattern is fixed for a given model, so the symbolic analysis (ordering) is redone only
  // when the size or the number of stored entries changes.
  const bool reanalyze = A.rows() != impl_->analyzed_rows || A.nonZeros() != impl_->analyzed_nnz;
  if (kind_ == SolverKind::kCholmod) {
    if (reanalyze) impl_->cholmod.analyzePattern(A);
    impl_->cholmod.factorize(A);
    if (impl_->cholmod.info() != Eigen::Success)
      throw SolidError(where + "CHOLMOD factorization failed: the solid system matrix M/h + C + (h/2) K' is "
                               "not positive definite (strongly compressed elements with an indefinite K': use "
                               "project_spd; or a diverging run)");
    x = impl_->cholmod.solve(b);
    stats_.iterations = 1;
    stats_.residual = 0;
  } else if (kind_ == SolverKind::kConjugateGradientIC) {
    run_cg(impl_->cg_ic, A, b, x, reanalyze, where);
  } else {
    run_cg(impl_->cg_jacobi, A, b, x, reanalyze, where);
  }
  impl_->analyzed_rows = A.rows();
  impl_->analyzed_nnz = A.nonZeros();
  if (!x.allFinite()) throw SolidError(where + "the linear solve produced non-finite velocities");
  stats_.seconds = clock.seconds();
}

}  // namespace tetfsi::solid
