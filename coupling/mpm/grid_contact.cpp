#include "coupling/mpm/grid_contact.hpp"

#include "fluid/mpm/reduce.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace tetfsi::mpm_contact {

MpmMembraneCoupling::MpmMembraneCoupling(mpm::MpmSolver& mpm, membrane::Membrane& membrane, ContactOptions options)
    : mpm_(mpm), mem_(membrane), opt_(options) {
  if (!(opt_.friction >= 0)) throw std::invalid_argument("grid contact: friction coefficient must be >= 0");
  if (!(opt_.distance_factor > 0)) throw std::invalid_argument("grid contact: distance factor must be > 0");
  const auto nn = static_cast<std::size_t>(mpm_.grid().num_nodes());
  at_.assign(nn, MembraneAtNode::zero());
  ps_.assign(nn, Vec3::Zero());
  grad_s_.assign(nn, Vec3::Zero());
  gap_.assign(nn, std::numeric_limits<double>::quiet_NaN());
}

double MpmMembraneCoupling::critical_time_step() const {
  return std::min(mpm_.critical_time_step(), mem_.critical_time_step());
}

ContactReport MpmMembraneCoupling::step(double h) {
  ContactReport rep;
  const auto& grid = mpm_.grid();
  using Clock = std::chrono::steady_clock;
  const auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  const auto t0 = Clock::now();
  // Steps 2 and 3: trial solutions.
  mpm_.trial_step(h);
  const auto t1 = Clock::now();
  mem_.compute_forces(h);
  mem_.trial_velocities(h);
  const auto t2 = Clock::now();

  // Step 4a: membrane mass, momentum, normals and mass-weighted positions on the grid.
  for (auto id : touched_) at_[id] = MembraneAtNode::zero();
  touched_.clear();
  const auto& X = mem_.positions();
  const auto& V = mem_.velocities();
  const auto& M = mem_.masses();
  mem_.node_normals(normals_);
  inside_.clear();
  fe_st_.clear();
  for (int k = 0; k < mem_.num_nodes(); ++k) {
    if (!grid.contains(X[k])) continue;  // outside the grid: no contact possible there
    inside_.push_back(k);
    fe_st_.push_back(grid.stencil_unchecked(X[k]));
    const auto& st = fe_st_.back();
    for (int c = 0; c < 8; ++c) {
      const auto id = st.node[c];
      auto& a = at_[id];
      if (!a.seen) {  // first touch: the list stays in a deterministic order, no sort needed
        a.seen = true;
        touched_.push_back(id);
      }
      a.m += st.N[c] * M[k];
      a.p += (st.N[c] * M[k]) * V[k];
      a.n += st.N[c] * normals_[k];
      a.x += (st.N[c] * M[k]) * X[k];
    }
  }

  // Step 4b: candidate nodes (shared by both bodies, approaching by eq. 52). The particle-side
  // trial momentum is the one the particles carry (see the header).
  const auto& ms = mpm_.node_mass();
  const double eps = mpm_.mass_threshold();
  const double dx = grid.dx;
  shared_.clear();
  for (auto id : touched_)
    if (at_[id].m > 0 && ms[id] > eps && at_[id].n.norm() > 0) shared_.push_back(id);
  mpm_.particle_trial_momenta(shared_, ps_, &grad_s_);
  candidates_.clear();
  for (auto id : shared_) {
    const double mr = at_[id].m, m_s = ms[id];
    Vec3 n = at_[id].n.normalized();
    // Orient the (two-sided) membrane normal towards body s, i.e. against the outward normal
    // n^s = sum_p N_Ip,i m_p of body s (eq. 51).
    if (n.dot(grad_s_[id]) > 0) n = -n;
    const Vec3 approach = m_s * at_[id].p - mr * ps_[id];
    if (!(approach.dot(n) > 0)) continue;  // eq. (52)
    at_[id].n = n;
    candidates_.push_back(id);
  }
  compute_gaps();
  // Steps 4c-4d. Forces act over h^n of the current step (eqs. 53, 55, 59); the impulses
  // h^n f do not depend on it.
  const double h_n = mpm_.momentum_step();
  for (auto id : candidates_) {
    const double g = gap_[id];
    gap_[id] = std::numeric_limits<double>::quiet_NaN();
    if (!(g < opt_.distance_factor * dx)) continue;
    const double mr = at_[id].m, m_s = ms[id];
    const Vec3 n = at_[id].n;
    const Vec3 pr = at_[id].p, p_s = ps_[id];
    const Vec3 approach = m_s * pr - mr * p_s;
    Vec3 f = -approach / ((mr + m_s) * h_n);  // eq. (55), force on r (see header for the sign)
    if (opt_.mode == ContactOptions::Mode::Slip) {
      const double fn = f.dot(n);  // eq. (56), < 0: pushes r back
      const Vec3 ft = f - fn * n;  // eq. (57)
      const double ft_norm = ft.norm(), limit = opt_.friction * std::abs(fn);
      f = fn * n + (ft_norm > limit ? Vec3(ft * (limit / ft_norm)) : ft);  // eq. (58)
    }
    at_[id].f = f;
    mpm_.add_node_impulse(id, -h_n * f);  // eq. (53) with f^s = -f^r
    rep.impulse_on_mpm -= h_n * f;
    rep.impulse_on_membrane += h_n * f;
    ++rep.contact_nodes;
  }

  // Eq. (59): membrane velocity correction from the grid contact accelerations, then eq. (47).
  double work_membrane = 0;
  if (rep.contact_nodes > 0) {
    auto& Vm = mem_.velocities();
    const auto& fixed = mem_.fixed();
    for (std::size_t j = 0; j < inside_.size(); ++j) {
      const int k = inside_[j];
      const auto& st = fe_st_[j];
      Vec3 dv = Vec3::Zero();
      for (int c = 0; c < 8; ++c) {
        const auto id = st.node[c];
        if (at_[id].m > 0) dv += st.N[c] * at_[id].f / at_[id].m;
      }
      const Vec3 v_trial = Vm[k];
      Vm[k] += h_n * dv;
      for (int a = 0; a < 3; ++a)
        if (fixed[k][a]) Vm[k][a] = 0;
      // Work of the contact force over the step with the mid-step velocity (v^{n-1/2} +
      // v^{n+1/2}) / 2, as for the membrane's external loads.
      const Vec3 v_old = v_trial - mem_.velocity_step() * mem_.forces()[k] / M[k];
      work_membrane += M[k] * (Vm[k] - v_trial).dot(0.5 * (v_old + Vm[k]));
    }
  }
  const auto t3 = Clock::now();
  mem_.update_positions(h);
  const auto t4 = Clock::now();
  mpm_.finish_step(h);
  const auto t5 = Clock::now();
  rep.seconds_particle_trial = seconds(t0, t1);
  rep.seconds_membrane = seconds(t1, t2) + seconds(t3, t4);
  rep.seconds_contact = seconds(t2, t3);
  rep.seconds_particle_update = seconds(t4, t5);
  // Work of the contact forces on both bodies, each measured where its kinetic energy lives
  // (FE nodes, particles); the loss is minus their sum.
  if (rep.contact_nodes > 0) {
    rep.work_on_membrane = work_membrane;
    rep.work_on_mpm = mpm_.impulse_work();
    rep.dissipated = -(work_membrane + mpm_.impulse_work());
  }
  contact_energy_ += rep.dissipated;
  return rep;
}

void MpmMembraneCoupling::compute_gaps() {
  // Real-distance confirmation: gap between the membrane (mass centre of its points around I)
  // and the surface of the nearest particle with N_Ip > 0, along n_I. One pass over the particles
  // of the cells around the candidate nodes (each node lies in 8 cells); min is order-free.
  if (candidates_.empty()) return;
  const auto& P = mpm_.particles();
  const auto& bins = mpm_.bins();
  for (auto id : candidates_) gap_[id] = std::numeric_limits<double>::infinity();
  // Per cell the smallest gap at each corner (cells in parallel, each writing its own 8 values),
  // then the minimum per node: exact, so the result does not depend on the number of threads.
  const auto& cells = mpm_.cells_around(candidates_);
  cell_gap_.resize(cells.size());
  auto cell_gaps = [&](std::size_t k) {
    const auto& c = cells[k];
    auto& g = cell_gap_[k];
    g.fill(std::numeric_limits<double>::infinity());
    const auto [b, e] = bins.cell(c[0], c[1], c[2]);
    std::int64_t ids[8];
    mpm::corner_nodes(mpm_.grid(), c, ids);
    for (auto it = b; it != e; ++it) {
      double f[3], N[8];
      mpm_.grid().fractions(P.x[*it], c, f);
      mpm::corner_weights(f, N);
      const double radius = 0.5 * std::cbrt(P.volume(*it));
      for (int q = 0; q < 8; ++q) {
        const auto id = ids[q];
        if (std::isnan(gap_[id]) || !(N[q] > 0)) continue;  // not a candidate / outside the support
        g[q] = std::min(g[q], (P.x[*it] - at_[id].x / at_[id].m).dot(at_[id].n) - radius);
      }
    }
  };
  mpm::for_each_index(cells.size(), P.size() >= mpm::CellBins::kParallelMin, cell_gaps);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    std::int64_t ids[8];
    mpm::corner_nodes(mpm_.grid(), cells[k], ids);
    for (int q = 0; q < 8; ++q)
      if (!std::isnan(gap_[ids[q]])) gap_[ids[q]] = std::min(gap_[ids[q]], cell_gap_[k][q]);
  }
}

CoupledEnergies MpmMembraneCoupling::energies() const {
  CoupledEnergies e;
  e.mpm = mpm_.energies();
  e.membrane = mem_.energies();
  e.contact = contact_energy_;
  return e;
}

}  // namespace tetfsi::mpm_contact
