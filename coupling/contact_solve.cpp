/// @file contact_solve.cpp
/// CoupledStepper::solve_with_contact: eq. (7) with the solids' contact active set
/// (coupled_stepper.hpp, step 5; solid/integrator/newmark.hpp for the constraint).
#include "coupling/coupled_stepper.hpp"

namespace tetfsi::coupling {

bool CoupledStepper::has_obstacles() const {
  for (const Solid& s : solids_)
    if (!s.integrator->obstacles().empty()) return true;
  return false;
}

CoupledSolveReport CoupledStepper::solve_with_contact(double h, CoupledSystem& sys, const std::vector<int>& unknown,
                                                      Eigen::VectorXd& u, Eigen::VectorXd& p) {
  if (!has_obstacles()) return solve(sys, unknown, u, p);
  // The solid rows without contact, kept once a round first adds the active constraints' penalty
  // rows to sys (a step without contact copies nothing).
  SparseMatrix A_free;
  Eigen::VectorXd b_free;
  bool kept = false;
  const auto without_contact = [&]() -> const SparseMatrix& { return kept ? A_free : sys.A; };
  const auto with_contact_rows = [&] {
    if (!kept) A_free = sys.A, b_free = sys.b, kept = true;
    sys.A = A_free;
    sys.b = b_free;
    for (const Solid& s : solids_) s.integrator->add_contact_rows(sys.A, sys.b, s.dof_offset);
  };
  bool warm = false;
  for (Solid& s : solids_) warm = s.integrator->warm_start_contacts(h, sys.A, s.dof_offset) || warm;
  if (warm) with_contact_rows();
  CoupledSolveReport report = solve(sys, unknown, u, p);
  report.contact_rounds = 1;
  for (int round = 0; round < kMaxContactRounds; ++round) {
    bool changed = false;
    for (Solid& s : solids_) changed = s.integrator->update_contacts(h, without_contact(), u, s.dof_offset) || changed;
    if (!changed) break;
    with_contact_rows();
    solver_->request_fresh_solve();  // the penalty rows changed A far beyond a step's drift
    const CoupledSolveReport again = solve(sys, unknown, u, p);
    report.iterations += again.iterations;
    report.setup_seconds += again.setup_seconds;
    report.solve_seconds += again.solve_seconds;
    report.residual = again.residual;
    report.factor_age = again.factor_age;
    ++report.contact_rounds;
  }
  report.contacts = 0;
  for (Solid& s : solids_) {
    s.integrator->finish_contacts(u, s.dof_offset);
    report.contacts += s.integrator->num_active_contacts();
  }
  return report;
}

}  // namespace tetfsi::coupling
