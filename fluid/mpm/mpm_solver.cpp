#include "fluid/mpm/mpm_solver.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tetfsi::mpm {
namespace {

template <class F>
void for_each_particle(std::size_t n, F&& f) {
  // Fixed grain and simple_partitioner: each particle is written by exactly one task, so the
  // result does not depend on scheduling.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p != r.end(); ++p) f(p);
                    },
                    tbb::simple_partitioner());
}

bool finite(const Vec3& v) { return v.allFinite(); }

}  // namespace

MpmSolver::MpmSolver(Grid grid, std::vector<Material> materials, Particles particles, MpmOptions options)
    : grid_(std::move(grid)), materials_(std::move(materials)), particles_(std::move(particles)),
      options_(options) {
  if (materials_.empty()) throw std::invalid_argument("MpmSolver: no materials given");
  for (const auto& m : materials_) m.validate();
  const auto n = particles_.size();
  if (particles_.x.size() != n || particles_.v.size() != n || particles_.stress.size() != n ||
      particles_.rho.size() != n || particles_.energy.size() != n || particles_.material.size() != n)
    throw std::invalid_argument("MpmSolver: particle arrays have different sizes");
  double total_mass = 0;
  for (std::size_t p = 0; p < n; ++p) {
    std::ostringstream where;
    where << "MpmSolver: particle " << p << " at (" << particles_.x[p].transpose() << ")";
    if (particles_.material[p] >= materials_.size())
      throw std::invalid_argument(where.str() + " has material index out of range");
    if (!(particles_.mass[p] > 0) || !(particles_.rho[p] > 0))
      throw std::invalid_argument(where.str() + " has non-positive mass or density");
    if (!grid_.contains(particles_.x[p])) throw std::invalid_argument(where.str() + " is outside the grid");
    total_mass += particles_.mass[p];
  }
  mask_ = grid_.build_constraint_mask();
  const auto nn = static_cast<std::size_t>(grid_.num_nodes());
  mass_.assign(nn, 0.0);
  mom_old_.assign(nn, Vec3::Zero());
  mom_new_.assign(nn, Vec3::Zero());
  force_.assign(nn, Vec3::Zero());
  mass_grad_.assign(nn, Vec3::Zero());
  mass_eps_ = n ? 1e-12 * total_mass / double(n) : 0.0;
}

double MpmSolver::critical_time_step() const {
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < particles_.size(); ++p) {
    const auto& mat = materials_[particles_.material[p]];
    const double rho = particles_.rho[p];
    const double pres = -particles_.stress[p].trace() / 3.0;
    const double c = mat.sound_speed(rho, pres) + particles_.v[p].norm();
    if (c > 0) dt = std::min(dt, grid_.h / c);
    if (mat.kind == Material::Kind::Fluid && mat.viscosity > 0)
      dt = std::min(dt, rho * grid_.h * grid_.h / (8.0 * mat.viscosity));
  }
  return options_.cfl * dt;
}

void MpmSolver::trial_step(double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("MpmSolver: time step must be positive");
  auto& P = particles_;
  const std::size_t n = P.size();
  // Step 1: reset the nodes used in the previous step (the grid is "rebuilt" each step).
  for (auto id : active_) {
    if (!vel_.empty()) {
      vel_[id].setZero();
      dvel_[id].setZero();
    }
    mass_[id] = 0;
    mom_old_[id].setZero();
    mom_new_[id].setZero();
    force_[id].setZero();
    mass_grad_[id].setZero();
  }
  active_.clear();
  stencils_.resize(n);
  for_each_particle(n, [&](std::size_t p) { stencils_[p] = grid_.stencil(P.x[p]); });

  // Step 2a (eqs. 60, 61, 51): serial scatter.
  for (std::size_t p = 0; p < n; ++p) {
    const auto& st = stencils_[p];
    for (int c = 0; c < 8; ++c) {
      const auto id = st.node[c];
      if (mass_[id] == 0.0 && mom_old_[id].isZero(0.0) && mass_grad_[id].isZero(0.0)) active_.push_back(id);
      mass_[id] += P.mass[p] * st.N[c];
      mom_old_[id] += (P.mass[p] * st.N[c]) * P.v[p];
      mass_grad_[id] += P.mass[p] * st.dN[c];
    }
  }
  std::sort(active_.begin(), active_.end());
  active_.erase(std::unique(active_.begin(), active_.end()), active_.end());
  // Step 2b: essential conditions on p^{n-1/2}; grid velocities v_I = p_I / m_I (0 if empty).
  if (vel_.size() != mass_.size()) vel_.assign(mass_.size(), Vec3::Zero());
  if (dvel_.size() != mass_.size()) dvel_.assign(mass_.size(), Vec3::Zero());
  for (auto id : active_) {
    for (int a = 0; a < 3; ++a)
      if (mask_[id][a]) mom_old_[id][a] = 0.0;
    vel_[id] = mass_[id] > mass_eps_ ? Vec3(mom_old_[id] / mass_[id]) : Vec3::Zero();
  }

  // Step 2c (eqs. 62, 63, 22, 25, 26): stress update with the grid velocities.
  for_each_particle(n, [&](std::size_t p) { update_particle_stress(p, dt); });

  // Step 2d (eqs. 17, 18): nodal forces, serial scatter.
  for (std::size_t p = 0; p < n; ++p) {
    const auto& st = stencils_[p];
    const double V = P.volume(p);
    const Vec3 body = P.mass[p] * options_.gravity;
    for (int c = 0; c < 8; ++c) force_[st.node[c]] += -V * (P.stress[p] * st.dN[c]) + st.N[c] * body;
  }
  // Step 2e (eq. 64) and grid conditions on f and p^{n+1/2}.
  for (auto id : active_) {
    for (int a = 0; a < 3; ++a)
      if (mask_[id][a]) force_[id][a] = 0.0;
    mom_new_[id] = mom_old_[id] + dt * force_[id];
  }
}

void MpmSolver::update_particle_stress(std::size_t p, double dt) {
  auto& P = particles_;
  const auto& st = stencils_[p];
  // Velocity gradient L_ij = sum_I v_iI N_I,j; D = sym L (eq. 23), W = skew L (eq. 24).
  Mat3 L = Mat3::Zero();
  for (int c = 0; c < 8; ++c) L += vel_[st.node[c]] * st.dN[c].transpose();
  const Mat3 D = 0.5 * (L + L.transpose());
  const Mat3 W = 0.5 * (L - L.transpose());
  const double trD = D.trace();
  const auto& mat = materials_[P.material[p]];
  const double rho_old = P.rho[p];
  // Mass conservation: rho^{n+1} = rho^n exp(-dt tr D).
  const double rho_new = rho_old * std::exp(-dt * trD);
  P.rho[p] = rho_new;
  if (mat.kind == Material::Kind::LinearElastic) {
    // Hypo-elastic Jaumann update (eqs. 22, 25): sigma += dt (C:D + W sigma - sigma W).
    // Eq. (22) is printed as sigma Omega + (sigma Omega)^T; with Omega_ij = (v_i,j - v_j,i)/2 as in
    // eq. (24) the objective rotation of sigma is W sigma - sigma W, which is what is used.
    const Mat3& s = P.stress[p];
    const Mat3 rate = mat.lame_lambda() * trD * Mat3::Identity() + 2.0 * mat.shear_modulus() * D;
    P.stress[p] = s + dt * (rate + W * s - s * W);
    return;
  }
  // Fluid (eq. 26): sigma = 2 mu D' - p I, p from the EOS with the energy equation
  //   dE = (s_visc : D dt) V/V0 - (p^n + p^{n+1})/2 dV/V0,
  // solved exactly for E^{n+1} because both EOS are linear in E (p = a + b E).
  const double V0 = P.mass[p] / mat.rho0;
  const double Vold = P.mass[p] / rho_old, Vnew = P.mass[p] / rho_new;
  const double dv = (Vnew - Vold) / V0;
  const Mat3 Ddev = D - (trD / 3.0) * Mat3::Identity();
  const Mat3 svisc = 2.0 * mat.viscosity * Ddev;
  const double w_visc = (svisc.cwiseProduct(Ddev)).sum() * dt * 0.5 * (Vold + Vnew) / V0;
  const double p_old = -P.stress[p].trace() / 3.0;
  const auto [a, b] = mat.eos_coefficients(rho_new);
  const double E = (P.energy[p] + w_visc - 0.5 * (p_old + a) * dv) / (1.0 + 0.5 * b * dv);
  P.energy[p] = E;
  P.stress[p] = svisc - (a + b * E) * Mat3::Identity();
}

void MpmSolver::finish_step(double dt) {
  auto& P = particles_;
  const std::size_t n = P.size();
  // Per node: velocity change (p^{n+1/2} - p^{n-1/2}) / m (eq. 65) and new velocity (eq. 19).
  for (auto id : active_) {
    const bool full = mass_[id] > mass_eps_;
    dvel_[id] = full ? Vec3((mom_new_[id] - mom_old_[id]) / mass_[id]) : Vec3::Zero();
    vel_[id] = full ? Vec3(mom_new_[id] / mass_[id]) : Vec3::Zero();
  }
  for_each_particle(n, [&](std::size_t p) {
    const auto& st = stencils_[p];
    Vec3 dv = Vec3::Zero(), vel = Vec3::Zero();
    for (int c = 0; c < 8; ++c) {
      dv += st.N[c] * dvel_[st.node[c]];
      vel += st.N[c] * vel_[st.node[c]];
    }
    P.v[p] += dv;
    P.x[p] += dt * vel;
  });
  for (std::size_t p = 0; p < n; ++p) {
    if (!finite(P.x[p]) || !finite(P.v[p]) || !P.stress[p].allFinite() || !std::isfinite(P.rho[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " became non-finite at step " << steps_ + 1 << " (t = " << time_ + dt
          << "); the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
    if (!grid_.contains(P.x[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " left the background grid at (" << P.x[p].transpose()
          << ") at t = " << time_ + dt;
      throw std::runtime_error(msg.str());
    }
  }
  time_ += dt;
  ++steps_;
}

void MpmSolver::apply_grid_conditions() {
  for (auto id : active_)
    for (int a = 0; a < 3; ++a)
      if (mask_[id][a]) mom_new_[id][a] = 0.0;
}

void MpmSolver::step(double dt) {
  trial_step(dt);
  finish_step(dt);
}

MpmEnergies MpmSolver::energies() const {
  MpmEnergies e;
  const auto& P = particles_;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const auto& mat = materials_[P.material[p]];
    e.kinetic += 0.5 * P.mass[p] * P.v[p].squaredNorm();
    e.gravity -= P.mass[p] * options_.gravity.dot(P.x[p]);
    if (mat.kind == Material::Kind::Fluid) {
      e.internal += P.energy[p] * P.mass[p] / mat.rho0;
    } else {
      // W = 1/2 sigma : eps V with eps = ((1+nu) sigma - nu tr(sigma) I) / E.
      const Mat3& s = P.stress[p];
      const Mat3 eps = ((1 + mat.poisson) * s - mat.poisson * s.trace() * Mat3::Identity()) / mat.youngs;
      e.internal += 0.5 * s.cwiseProduct(eps).sum() * P.volume(p);
    }
  }
  return e;
}

Vec3 MpmSolver::total_momentum() const {
  Vec3 m = Vec3::Zero();
  for (std::size_t p = 0; p < particles_.size(); ++p) m += particles_.mass[p] * particles_.v[p];
  return m;
}

}  // namespace tetfsi::mpm
