#include "coupling/solvers/coupled_solver.hpp"

#include "coupling/solvers/solver_impls.hpp"

namespace tetfsi::coupling {

CoupledSolverKind parse_coupled_solver_kind(const std::string& name) {
  if (name == "umfpack") return CoupledSolverKind::Umfpack;
  if (name == "bicgstab") return CoupledSolverKind::BiCGSTAB;
  if (name == "schur_cg") return CoupledSolverKind::SchurCG;
  throw std::invalid_argument("unknown coupled solver '" + name + "' (expected umfpack, bicgstab or schur_cg)");
}

std::string to_string(CoupledSolverKind kind) {
  switch (kind) {
    case CoupledSolverKind::Umfpack: return "umfpack";
    case CoupledSolverKind::BiCGSTAB: return "bicgstab";
    case CoupledSolverKind::SchurCG: return "schur_cg";
  }
  return "unknown";
}

std::unique_ptr<CoupledSolver> make_coupled_solver(CoupledSolverKind kind, CoupledSolverOptions options) {
  switch (kind) {
    case CoupledSolverKind::Umfpack: return std::make_unique<detail::UmfpackSolver>(std::move(options));
    case CoupledSolverKind::BiCGSTAB: return std::make_unique<detail::BiCGSTABSolver>(std::move(options));
    case CoupledSolverKind::SchurCG: return std::make_unique<detail::SchurCGSolver>(std::move(options));
  }
  throw std::invalid_argument("unknown coupled solver kind");
}

}  // namespace tetfsi::coupling
