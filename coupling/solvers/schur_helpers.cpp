// Helpers shared by the iterative coupled solvers.
#include <sstream>

#include "coupling/solvers/solver_impls.hpp"

namespace tetfsi::coupling::detail {

SparseMatrix approximate_schur_complement(const CoupledSystem& s) {
  const Eigen::VectorXd inv_diag_A = s.A.diagonal().cwiseInverse();
  const SparseMatrix HDinv = s.H * inv_diag_A.asDiagonal();
  SparseMatrix S = s.P + SparseMatrix(HDinv * SparseMatrix(s.H.transpose()));
  S.makeCompressed();
  return S;
}

void require_converged(const CoupledSolveReport& report, double tolerance) {
  if (report.residual.max() <= tolerance) return;
  std::ostringstream msg;
  msg << report.solver << ": did not converge after " << report.iterations
      << " iterations (relative residual solid " << report.residual.solid << ", fluid "
      << report.residual.fluid << ", tolerance " << tolerance << ")";
  throw CoupledSolveError(msg.str());
}

void split_and_check(const CoupledSystem& s, const Eigen::VectorXd& x, double tolerance, CoupledSolveReport& report,
                     Eigen::VectorXd& u, Eigen::VectorXd& p) {
  u = x.head(s.num_solid_dofs());
  p = x.tail(s.num_pressures());
  report.residual = residuals(s, u, p);
  require_converged(report, tolerance);
}

}  // namespace tetfsi::coupling::detail
