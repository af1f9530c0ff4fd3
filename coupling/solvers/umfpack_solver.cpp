// UMFPACK: the direct reference solver of eq. (7) (see coupled_solver.hpp).
#include <Eigen/UmfPackSupport>

#include "coupling/solvers/solver_impls.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::coupling::detail {

CoupledSolveReport UmfpackSolver::solve(const CoupledSystem& s, Eigen::VectorXd& u, Eigen::VectorXd& p) {
  s.check_sizes();
  const int n = s.num_solid_dofs(), m = s.num_pressures();
  CoupledSolveReport report;
  report.solver = "umfpack";
  Stopwatch clock;
  // 64-bit indices (umfpack_dl): the int interface runs out of index space on large systems.
  using LongMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;
  LongMatrix K = paper_form_matrix(s).cast<double>();
  K.makeCompressed();
  Eigen::UmfPackLU<LongMatrix> lu;
  lu.compute(K);
  report.setup_seconds = clock.lap();
  if (lu.info() != Eigen::Success) throw CoupledSolveError("umfpack: factorization failed (singular system?)");
  Eigen::VectorXd rhs(n + m);
  rhs << s.b, s.r;
  const Eigen::VectorXd x = lu.solve(rhs);
  report.solve_seconds = clock.lap();
  if (lu.info() != Eigen::Success || !x.allFinite()) throw CoupledSolveError("umfpack: solve failed");
  split_and_check(s, x, options_.tolerance, report, u, p);
  return report;
}

}  // namespace tetfsi::coupling::detail
