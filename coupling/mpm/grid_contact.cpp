#include "coupling/mpm/grid_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tetfsi::mpm_contact {

MpmMembraneCoupling::MpmMembraneCoupling(mpm::MpmSolver& mpm, membrane::Membrane& membrane, ContactOptions options)
    : mpm_(mpm), mem_(membrane), opt_(options) {
  if (!(opt_.friction >= 0)) throw std::invalid_argument("grid contact: friction coefficient must be >= 0");
  if (!(opt_.distance_factor > 0)) throw std::invalid_argument("grid contact: distance factor must be > 0");
  const auto nn = static_cast<std::size_t>(mpm_.grid().num_nodes());
  mr_.assign(nn, 0.0);
  pr_.assign(nn, Vec3::Zero());
  nr_.assign(nn, Vec3::Zero());
  xr_.assign(nn, Vec3::Zero());
  gap_.assign(nn, std::numeric_limits<double>::quiet_NaN());
  fr_.assign(nn, Vec3::Zero());
}

double MpmMembraneCoupling::critical_time_step() const {
  return std::min(mpm_.critical_time_step(), mem_.critical_time_step());
}

ContactReport MpmMembraneCoupling::step(double dt) {
  ContactReport rep;
  const auto& grid = mpm_.grid();
  // Steps 2 and 3: trial solutions.
  mpm_.trial_step(dt);
  mem_.compute_forces(dt);
  mem_.trial_velocities(dt);

  // Step 4a: membrane mass, momentum, normals and mass-weighted positions on the grid.
  for (auto id : touched_) {
    mr_[id] = 0;
    pr_[id].setZero();
    nr_[id].setZero();
    xr_[id].setZero();
    fr_[id].setZero();
  }
  touched_.clear();
  const auto& X = mem_.positions();
  const auto& V = mem_.velocities();
  const auto& M = mem_.masses();
  const auto normals = mem_.node_normals();
  std::vector<int> inside;
  std::vector<mpm::Stencil> fe_st;
  inside.reserve(X.size());
  fe_st.reserve(X.size());
  for (int k = 0; k < mem_.num_nodes(); ++k) {
    if (!grid.contains(X[k])) continue;  // outside the grid: no contact possible there
    inside.push_back(k);
    fe_st.push_back(grid.stencil(X[k]));
    const auto& st = fe_st.back();
    for (int c = 0; c < 8; ++c) {
      const auto id = st.node[c];
      if (mr_[id] == 0 && nr_[id].isZero(0.0)) touched_.push_back(id);
      mr_[id] += st.N[c] * M[k];
      pr_[id] += (st.N[c] * M[k]) * V[k];
      nr_[id] += st.N[c] * normals[k];
      xr_[id] += (st.N[c] * M[k]) * X[k];
    }
  }
  std::sort(touched_.begin(), touched_.end());
  touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());

  // Steps 4b: candidate nodes (shared by both bodies, approaching by eq. 52).
  auto& ps = mpm_.node_momentum();
  const auto& ms = mpm_.node_mass();
  const double eps = mpm_.mass_threshold();
  const auto& grad_s = mpm_.node_mass_gradient();
  const double h = grid.h;
  std::vector<std::int64_t> candidates;
  for (auto id : touched_) {
    const double mr = mr_[id], m_s = ms[id];
    if (!(mr > 0) || !(m_s > eps) || nr_[id].norm() == 0) continue;
    Vec3 n = nr_[id].normalized();
    // Orient the (two-sided) membrane normal towards body s, i.e. against the outward normal
    // n^s = sum_p N_Ip,i m_p of body s (eq. 51).
    if (n.dot(grad_s[id]) > 0) n = -n;
    const Vec3 approach = m_s * pr_[id] - mr * ps[id];
    if (!(approach.dot(n) > 0)) continue;  // eq. (52)
    nr_[id] = n;
    gap_[id] = std::numeric_limits<double>::infinity();
    candidates.push_back(id);
  }
  // Real-distance confirmation: gap between the membrane (mass centre of its points around I)
  // and the surface of the nearest particle in the support of I, along n_I.
  if (!candidates.empty()) {
    const auto& P = mpm_.particles();
    const auto& pst = mpm_.stencils();
    for (std::size_t p = 0; p < P.size(); ++p) {
      const double radius = 0.5 * std::cbrt(P.volume(p));
      for (int c = 0; c < 8; ++c) {
        const auto id = pst[p].node[c];
        if (std::isnan(gap_[id]) || pst[p].N[c] <= 0) continue;  // not a candidate node
        const double g = (P.x[p] - xr_[id] / mr_[id]).dot(nr_[id]) - radius;
        gap_[id] = std::min(gap_[id], g);
      }
    }
  }
  // Steps 4c-4d.
  for (auto id : candidates) {
    const double gap = gap_[id];
    gap_[id] = std::numeric_limits<double>::quiet_NaN();
    if (!(gap < opt_.distance_factor * h)) continue;
    const double mr = mr_[id], m_s = ms[id];
    const Vec3 n = nr_[id];
    const Vec3 pr = pr_[id], p_s = ps[id];
    const Vec3 approach = m_s * pr - mr * p_s;
    Vec3 f = -approach / ((mr + m_s) * dt);  // eq. (55), force on r (see header for the sign)
    if (opt_.mode == ContactOptions::Mode::Slip) {
      const double fn = f.dot(n);  // eq. (56), < 0: pushes r back
      const Vec3 ft = f - fn * n;  // eq. (57)
      const double ft_norm = ft.norm(), limit = opt_.friction * std::abs(fn);
      f = fn * n + (ft_norm > limit ? Vec3(ft * (limit / ft_norm)) : ft);  // eq. (58)
    }
    fr_[id] = f;
    const Vec3 ps_new = p_s - dt * f;  // eq. (53) with f^s = -f^r
    rep.dissipated += 0.5 * (p_s.squaredNorm() - ps_new.squaredNorm()) / m_s;  // MPM side, on the grid
    ps[id] = ps_new;
    rep.impulse_on_mpm -= dt * f;
    rep.impulse_on_membrane += dt * f;
    ++rep.contact_nodes;
  }
  mpm_.apply_grid_conditions();

  // Eq. (59): membrane velocity correction from the grid contact accelerations, then eq. (47).
  if (rep.contact_nodes > 0) {
    auto& Vm = mem_.velocities();
    const auto& fixed = mem_.fixed();
    for (std::size_t j = 0; j < inside.size(); ++j) {
      const int k = inside[j];
      const auto& st = fe_st[j];
      Vec3 dv = Vec3::Zero();
      for (int c = 0; c < 8; ++c) {
        const auto id = st.node[c];
        if (mr_[id] > 0) dv += st.N[c] * fr_[id] / mr_[id];
      }
      const double ke_before = 0.5 * M[k] * Vm[k].squaredNorm();
      Vm[k] += dt * dv;
      for (int a = 0; a < 3; ++a)
        if (fixed[k][a]) Vm[k][a] = 0;
      rep.dissipated += ke_before - 0.5 * M[k] * Vm[k].squaredNorm();  // membrane side, at its nodes
    }
  }
  mem_.update_positions(dt);
  mpm_.finish_step(dt);
  contact_energy_ += rep.dissipated;
  return rep;
}

CoupledEnergies MpmMembraneCoupling::energies() const {
  CoupledEnergies e;
  e.mpm = mpm_.energies();
  e.membrane = mem_.energies();
  e.contact = contact_energy_;
  return e;
}

}  // namespace tetfsi::mpm_contact
