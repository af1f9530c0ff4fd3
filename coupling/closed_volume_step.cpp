/// @file closed_volume_step.cpp
/// CoupledStepper's part of keeping the closed fluid regions' volumes (closed_regions.hpp):
/// the start-velocity projection (correction 1) and the step's solution corrected by the responses
/// to the regions' unit dilatations (correction 3). Correction 2 is the source that step_once adds
/// to the fluid rows.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "coupling/coupled_stepper.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::coupling {

void CoupledStepper::begin_closed_volumes(double h, const std::vector<int>& unknown, CoupledStepReport& report) {
  if (!settings_.keep_closed_volumes || settings_.scheme != CouplingScheme::kSimultaneous) return;
  const std::vector<char> fixed = prescribed_dofs();
  if (closed_volumes_.begin_step(fluid_.mesh(), unknown, fluid_.boundary(), solid_node_of_vertex(), fixed,
                                 mesh_.vertices) == 0)
    return;
  Eigen::VectorXd masses(num_solid_dofs_ / 3);
  for (const Solid& s : solids_) masses.segment(s.dof_offset / 3, s.model->num_nodes()) = s.model->lumped_masses();
  Eigen::VectorXd u = solid_velocities();
  closed_volumes_.project_start_velocity(u, masses, fixed, report.closed_volume);
  for (Solid& s : solids_) s.integrator->set_velocity(u.segment(s.dof_offset, 3 * s.model->num_nodes()));
  closed_volumes_.predict_motion(mesh_vertices_at(solid_positions() + h * u));
}

double CoupledStepper::closed_volume_tolerance(int c) const {
  // 1e-4 of the smaller of the region's volume and that of the solids on its boundary.
  const ClosedRegion& region = closed_volumes_.regions()[c];
  const std::vector<int> node = solid_node_of_vertex();
  std::vector<char> around(solids_.size(), 0);
  for (const auto& f : region.faces)
    for (int v : f)
      for (std::size_t i = 0; i < solids_.size(); ++i)
        if (node[v] >= 0 && 3 * node[v] >= solids_[i].dof_offset &&
            3 * node[v] < solids_[i].dof_offset + 3 * solids_[i].model->num_nodes())
          around[i] = 1;
  double solids = 0;
  for (std::size_t i = 0; i < solids_.size(); ++i) {
    if (!around[i]) continue;
    const Eigen::VectorXd x = solids_[i].integrator->positions();
    for (const auto& t : solids_[i].model->tets())
      solids += mesh::signed_volume(x.segment<3>(3 * t[0]), x.segment<3>(3 * t[1]), x.segment<3>(3 * t[2]),
                                    x.segment<3>(3 * t[3]));
  }
  return 1e-4 * std::min(closed_volumes_.reference_volumes().at(region.key), std::abs(solids));
}

void CoupledStepper::restore_closed_volumes(double h, CoupledSystem& sys, const std::vector<int>& unknown,
                                            Eigen::VectorXd& u, Eigen::VectorXd& p, CoupledStepReport& report) {
  const int k = static_cast<int>(closed_volumes_.regions().size());
  if (k == 0) return;
  const auto excess = [&](const Eigen::VectorXd& u_end) {  // V_c(x^{n+1}) − V₀_c
    const std::vector<double> e = closed_volumes_.excess(mesh_vertices_at(end_solid_positions(h, u_end)));
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(e.data(), k));
  };
  Eigen::VectorXd e = excess(u);
  bool within = true;
  for (int c = 0; c < k; ++c) within = within && std::abs(e[c]) <= closed_volume_tolerance(c);
  if (within) return;
  // The responses to each region's unit dilatation: the same matrix, b = 0, r = w_c.
  const Eigen::VectorXd b = sys.b, r = sys.r;
  std::vector<Eigen::VectorXd> du(k), dp(k);
  sys.b.setZero();
  for (int c = 0; c < k; ++c) {
    sys.r = closed_volumes_.unit_source(c, fluid_.mesh(), unknown, sys.num_pressures());
    du[c] = Eigen::VectorXd::Zero(u.size());
    dp[c] = Eigen::VectorXd::Zero(p.size());
    const CoupledSolveReport again = solver_->solve(sys, du[c], dp[c]);
    report.solve.iterations += again.iterations;
    report.solve.setup_seconds += again.setup_seconds;
    report.solve.solve_seconds += again.solve_seconds;
    ++report.closed_volume.resolves;
  }
  sys.b = b;
  sys.r = r;
  // Newton on V_c(x^{n+1}(u + Σ s_d du_d)) = V₀_c; its Jacobian (h/2) a_cᵀ du_d is that of the
  // linear part (≈ h/2 times the identity), enough for the cubic's small remainder.
  Eigen::MatrixXd jacobian(k, k);
  for (int c = 0; c < k; ++c)
    for (int d = 0; d < k; ++d) jacobian(c, d) = 0.5 * h * closed_volumes_.gradient(c).dot(du[d]);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(jacobian);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(k);
  for (int iteration = 0; iteration < 4; ++iteration) {
    s -= lu.solve(e);
    Eigen::VectorXd u_s = u;
    for (int d = 0; d < k; ++d) u_s += s[d] * du[d];
    e = excess(u_s);
  }
  for (int d = 0; d < k; ++d) {
    u += s[d] * du[d];
    p += s[d] * dp[d];
  }
}

}  // namespace tetfsi::coupling
