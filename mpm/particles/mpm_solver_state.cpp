/// @file mpm_solver_state.cpp
/// MpmSolver::write_state / read_state: particles, grid arrays, step lengths and counters in a
/// checkpoint (support/binary_stream.hpp). The cell bins are rebuilt at the next step: from the
/// same positions they come out the same (stable sort by cell).
#include "mpm/particles/mpm_solver.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::mpm {

void MpmSolver::write_state(BinaryWriter& out) const {
  const Particles& P = particles_;
  out(P.mass, P.x, P.v, P.stress, P.rho, P.energy, P.material);
  out(box_lo_, box_hi_, mass_, mom_old_, mom_new_, force_, impulse_, impulse_nodes_, vel_, dvel_, dvel_imp_, work_,
      critical_h_, impulse_work_, h_prev_, h_n_, h_step_, time_, steps_);
}

void MpmSolver::read_state(BinaryReader& in) {
  Particles& P = particles_;
  in(P.mass, P.x, P.v, P.stress, P.rho, P.energy, P.material);
  const std::size_t n = P.mass.size();
  if (P.x.size() != n || P.v.size() != n || P.stress.size() != n || P.rho.size() != n || P.energy.size() != n ||
      P.material.size() != n)
    in.fail("particle arrays of different sizes");
  for (auto m : P.material)
    if (m >= materials_.size()) in.fail("a particle material out of range");
  const std::size_t nodes = mass_.size();
  in(box_lo_, box_hi_, mass_, mom_old_, mom_new_, force_, impulse_, impulse_nodes_, vel_, dvel_, dvel_imp_, work_,
     critical_h_, impulse_work_, h_prev_, h_n_, h_step_, time_, steps_);
  for (std::size_t size : {mass_.size(), mom_old_.size(), mom_new_.size(), force_.size(), impulse_.size(), vel_.size(),
                           dvel_.size(), dvel_imp_.size()})
    if (size != nodes) in.fail("grid arrays of another grid");
  for (auto id : impulse_nodes_)
    if (id < 0 || static_cast<std::size_t>(id) >= nodes) in.fail("an impulse node outside the grid");
  bins_current_ = false;
}

}  // namespace tetfsi::mpm
