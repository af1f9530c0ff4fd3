/// @file contact_solve.cpp
/// CoupledStepper::solve_with_contact: eq. (7) with the solids' contact active set
/// and the solids' surface contact (coupled_stepper.hpp, step 5; solid/integrator/newmark.hpp and
/// solid/contact/surface_contact.hpp for the constraints).
#include <algorithm>

#include "coupling/coupled_stepper.hpp"

namespace tetfsi::coupling {

bool CoupledStepper::has_obstacles() const {
  for (const Solid& s : solids_)
    if (!s.integrator->obstacles().empty()) return true;
  return false;
}

std::vector<char> CoupledStepper::prescribed_dofs() const {
  std::vector<char> prescribed(num_solid_dofs_, 0);
  for (const Solid& s : solids_)
    std::copy(s.integrator->fixed_dofs().begin(), s.integrator->fixed_dofs().end(), prescribed.begin() + s.dof_offset);
  return prescribed;
}

void CoupledStepper::enable_surface_contact(const solid::SurfaceContactSettings& settings,
                                            const std::vector<char>& self_contact) {
  surface_contact_ = std::make_unique<solid::SurfaceContact>(settings);
  for (std::size_t i = 0; i < solids_.size(); ++i)
    surface_contact_->add_solid(solids_[i].model->tets(), solids_[i].model->reference_positions(),
                                solids_[i].model->lumped_masses(), solids_[i].dof_offset,
                                i < self_contact.size() && self_contact[i]);
}

Eigen::VectorXd CoupledStepper::end_solid_positions(double h, const Eigen::VectorXd& u) const {
  Eigen::VectorXd x(num_solid_dofs_);
  for (const Solid& s : solids_) {
    const int n = 3 * s.model->num_nodes();
    x.segment(s.dof_offset, n) = s.model->reference_positions() + s.integrator->end_displacement(h, u.segment(s.dof_offset, n));
  }
  return x;
}

Eigen::Vector3d CoupledStepper::contact_force(int i) const {
  Eigen::Vector3d f = solids_[i].integrator->contact_force();
  if (surface_contact_) f += surface_contact_->contact_force(i);
  return f;
}

CoupledSolveReport CoupledStepper::solve_with_contact(double h, CoupledSystem& sys, const std::vector<int>& unknown,
                                                      Eigen::VectorXd& u, Eigen::VectorXd& p) {
  const bool pairs = has_surface_contact();
  if (!has_obstacles() && !pairs) return solve(sys, unknown, u, p);
  if (pairs) surface_contact_->begin_step(h, solid_positions(), solid_velocities(), prescribed_dofs());
  // The solid rows without contact, kept once a round first adds the active constraints' penalty
  // rows to sys (a step without contact copies nothing).
  SparseMatrix A_free;
  Eigen::VectorXd b_free;
  bool kept = false;
  const auto with_contact_rows = [&] {
    if (!kept) A_free = sys.A, b_free = sys.b, kept = true;
    sys.A = A_free;
    sys.b = b_free;
    for (const Solid& s : solids_) s.integrator->add_contact_rows(sys.A, sys.b, s.dof_offset);
    if (pairs) surface_contact_->add_rows(sys.A, sys.b);
  };
  bool warm = false;
  for (Solid& s : solids_) warm = s.integrator->warm_start_contacts(h) || warm;
  if (pairs) warm = surface_contact_->warm_start() || warm;
  if (warm) with_contact_rows();
  CoupledSolveReport report = solve(sys, unknown, u, p);
  report.contact_rounds = 1;
  for (int round = 0; round < kMaxContactRounds; ++round) {
    bool changed = false;
    for (Solid& s : solids_) changed = s.integrator->update_contacts(h, u, s.dof_offset) || changed;
    if (pairs) changed = surface_contact_->update(u) || changed;
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
  if (pairs) {
    surface_contact_->finish(u);  // forces, then friction on u
    report.contacts += surface_contact_->num_active();
  }
  for (Solid& s : solids_) {
    s.integrator->finish_contacts(u, s.dof_offset);
    report.contacts += s.integrator->num_active_contacts();
  }
  return report;
}

}  // namespace tetfsi::coupling
