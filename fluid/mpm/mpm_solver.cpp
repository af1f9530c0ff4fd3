#include "fluid/mpm/mpm_solver.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tetfsi::mpm {
namespace {

constexpr std::size_t kGrain = 512;  // fixed grain of the deterministic reductions

/// Bound of eq. (21) for one particle, h / (c + |v|), and the explicit viscous bound
/// rho h^2 / (8 mu) of viscous fluids [s].
/// `p_modulus` is lambda + 2 G of a linear-elastic material (precomputed: saves the divisions of
/// Material::sound_speed in the particle loop).
double particle_step_bound(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v,
                           double h) {
  double dt = std::numeric_limits<double>::infinity();
  const double sound = mat.kind == Material::Kind::LinearElastic ? std::sqrt(p_modulus / rho)
                                                                 : mat.sound_speed(rho, -stress.trace() / 3.0);
  const double c = sound + v.norm();
  if (c > 0) dt = h / c;
  if (mat.kind == Material::Kind::Fluid && mat.viscosity > 0) dt = std::min(dt, rho * h * h / (8.0 * mat.viscosity));
  return dt;
}

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
  for (const auto& m : materials_)
    lame_.push_back({m.lame_lambda(), 2.0 * m.shear_modulus(), m.lame_lambda() + 2 * m.shear_modulus()});
  mask_ = grid_.build_constraint_mask();
  const auto nn = static_cast<std::size_t>(grid_.num_nodes());
  mass_.assign(nn, 0.0);
  for (auto* f : {&mom_old_, &mom_new_, &force_, &mass_grad_, &impulse_, &vel_, &dvel_, &dvel_imp_})
    f->assign(nn, Vec3::Zero());
  mass_eps_ = n ? 1e-12 * total_mass / double(n) : 0.0;
  critical_dt_ = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < n; ++p)
    critical_dt_ = std::min(critical_dt_, particle_step_bound(materials_[particles_.material[p]],
                                                              lame_[particles_.material[p]][2], particles_.rho[p],
                                                              particles_.stress[p], particles_.v[p], grid_.h));
  critical_dt_ *= options_.cfl;
}

template <class F>
void MpmSolver::for_each_box_node(F&& f) const {
  const int nx = box_hi_[0] - box_lo_[0] + 1, ny = box_hi_[1] - box_lo_[1] + 1, nz = box_hi_[2] - box_lo_[2] + 1;
  if (nx <= 0 || ny <= 0 || nz <= 0) return;
  if (std::int64_t(nx) * ny * nz < 8192) {  // small box: task overhead dominates
    for (int row = 0; row < ny * nz; ++row) {
      const std::int64_t first = grid_.node_index(box_lo_[0], box_lo_[1] + row % ny, box_lo_[2] + row / ny);
      for (std::int64_t id = first; id < first + nx; ++id) f(id);
    }
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, ny * nz, 16), [&](const tbb::blocked_range<int>& r) {
    for (int row = r.begin(); row != r.end(); ++row) {
      const std::int64_t first = grid_.node_index(box_lo_[0], box_lo_[1] + row % ny, box_lo_[2] + row / ny);
      for (std::int64_t id = first; id < first + nx; ++id) f(id);
    }
  });
}

void MpmSolver::trial_step(double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("MpmSolver: time step must be positive");
  auto& P = particles_;
  // Step 1: reset the nodes of the previous step's box (the grid is "rebuilt" each step).
  for_each_box_node([&](std::int64_t id) {
    mass_[id] = 0;
    for (auto* f : {&mom_old_, &mom_new_, &force_, &mass_grad_, &impulse_, &vel_, &dvel_, &dvel_imp_}) (*f)[id].setZero();
  });
  impulse_nodes_.clear();
  bins_.build(grid_, P.x);
  if (bins_.empty()) {
    box_lo_ = {0, 0, 0};
    box_hi_ = {-1, -1, -1};
    return;
  }
  for (int a = 0; a < 3; ++a) {
    box_lo_[a] = bins_.lo()[a];
    box_hi_[a] = bins_.hi()[a] + 1;
  }

  // Step 2a (eqs. 60, 61, 51): coloured parallel scatter.
  bins_.for_each_coloured([&](std::size_t p) {
    const Stencil st = grid_.stencil_unchecked(P.x[p]);
    const double m = P.mass[p];
    const Vec3 mv = m * P.v[p];
    for (int c = 0; c < 8; ++c) {
      const auto id = st.node[c];
      mass_[id] += m * st.N[c];
      mom_old_[id] += st.N[c] * mv;
      mass_grad_[id] += m * st.dN[c];
    }
  });
  // Step 2b: essential conditions on p^{n-1/2}; grid velocities v_I = p_I / m_I (0 if empty).
  for_each_box_node([&](std::int64_t id) {
    for (int a = 0; a < 3; ++a)
      if (mask_[id][a]) mom_old_[id][a] = 0.0;
    vel_[id] = mass_[id] > mass_eps_ ? Vec3(mom_old_[id] / mass_[id]) : Vec3::Zero();
  });
  // Steps 2c, 2d (eqs. 62, 63, 22, 25, 26; 17, 18): stress update, then the particle's nodal
  // forces, in the same coloured pass.
  bins_.for_each_coloured([&](std::size_t p) {
    const Stencil st = grid_.stencil_unchecked(P.x[p]);
    update_particle_stress(p, dt, st);
    const double V = P.volume(p);
    const Vec3 body = P.mass[p] * options_.gravity;
    const Mat3& sigma = P.stress[p];
    for (int c = 0; c < 8; ++c) force_[st.node[c]] += -V * (sigma * st.dN[c]) + st.N[c] * body;
  });
  // Step 2e (eq. 64) and grid conditions on f and p^{n+1/2}.
  for_each_box_node([&](std::int64_t id) {
    for (int a = 0; a < 3; ++a)
      if (mask_[id][a]) force_[id][a] = 0.0;
    mom_new_[id] = mom_old_[id] + dt * force_[id];
  });
}

void MpmSolver::update_particle_stress(std::size_t p, double dt, const Stencil& st) {
  auto& P = particles_;
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
    const auto& lm = lame_[P.material[p]];  // lambda, 2 G
    const Mat3 rate = lm[0] * trD * Mat3::Identity() + lm[1] * D;
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

void MpmSolver::add_node_impulse(std::int64_t node, const Vec3& dp) {
  Vec3 d = dp;
  for (int a = 0; a < 3; ++a)
    if (mask_[node][a]) d[a] = 0.0;
  if (impulse_[node].isZero(0.0)) impulse_nodes_.push_back(node);
  impulse_[node] += d;
}

void MpmSolver::particle_trial_momenta(const std::vector<std::int64_t>& nodes, std::vector<Vec3>& out) {
  if (marked_.size() != mass_.size()) marked_.assign(mass_.size(), 0);
  const std::int64_t nx = grid_.cells[0] + 1, ny = grid_.cells[1] + 1;
  // Cells around the nodes (each node lies in 8 cells), ascending and unique.
  cells_.clear();
  for (auto node : nodes) {
    marked_[node] = 1;
    out[node].setZero();
    const int i = static_cast<int>(node % nx), j = static_cast<int>((node / nx) % ny), k = static_cast<int>(node / (nx * ny));
    for (int ck = std::max(k - 1, 0); ck <= std::min(k, grid_.cells[2] - 1); ++ck)
      for (int cj = std::max(j - 1, 0); cj <= std::min(j, grid_.cells[1] - 1); ++cj)
        for (int ci = std::max(i - 1, 0); ci <= std::min(i, grid_.cells[0] - 1); ++ci)
          cells_.push_back(ci + std::int64_t(grid_.cells[0]) * (cj + std::int64_t(grid_.cells[1]) * ck));
  }
  std::sort(cells_.begin(), cells_.end());
  cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
  for (auto cell : cells_) {
    const int ci = static_cast<int>(cell % grid_.cells[0]), cj = static_cast<int>((cell / grid_.cells[0]) % grid_.cells[1]);
    const int ck = static_cast<int>(cell / (std::int64_t(grid_.cells[0]) * grid_.cells[1]));
    const auto [b, e] = bins_.cell(ci, cj, ck);
    for (auto it = b; it != e; ++it) {
      const std::size_t p = *it;
      const Stencil st = stencil(p);
      Vec3 v = particles_.v[p];
      for (int c = 0; c < 8; ++c) {
        const auto id = st.node[c];
        if (mass_[id] > mass_eps_) v += st.N[c] * (mom_new_[id] - mom_old_[id]) / mass_[id];
      }
      for (int c = 0; c < 8; ++c)
        if (marked_[st.node[c]]) out[st.node[c]] += (particles_.mass[p] * st.N[c]) * v;
    }
  }
  for (auto node : nodes) marked_[node] = 0;
}

void MpmSolver::finish_step(double dt) {
  auto& P = particles_;
  const std::size_t n = P.size();
  const bool impulses = !impulse_nodes_.empty();
  // Per node: velocity change (p^{n+1/2} - p^{n-1/2}) / m (eq. 65), its impulse part, and the new
  // velocity (eq. 19).
  for_each_box_node([&](std::int64_t id) {
    const bool full = mass_[id] > mass_eps_;
    const Vec3 p_new = mom_new_[id] + impulse_[id];
    dvel_[id] = full ? Vec3((p_new - mom_old_[id]) / mass_[id]) : Vec3::Zero();
    dvel_imp_[id] = full ? Vec3(impulse_[id] / mass_[id]) : Vec3::Zero();
    vel_[id] = full ? Vec3(p_new / mass_[id]) : Vec3::Zero();
  });
  // Grid-to-particle update with the reductions of this step: kinetic energy given by the
  // impulses, the next critical step (eq. 21) and the first invalid particle.
  struct Acc {
    double work = 0;
    double dt = std::numeric_limits<double>::infinity();
    std::size_t bad = std::numeric_limits<std::size_t>::max();
  };
  const double h = grid_.h;
  const Acc acc = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, n, kGrain), Acc{},
      [&](const tbb::blocked_range<std::size_t>& r, Acc a) {
        for (std::size_t p = r.begin(); p != r.end(); ++p) {
          const Stencil st = grid_.stencil_unchecked(P.x[p]);
          Vec3 dv = Vec3::Zero(), vel = Vec3::Zero(), dvi = Vec3::Zero();
          for (int c = 0; c < 8; ++c) {
            dv += st.N[c] * dvel_[st.node[c]];
            vel += st.N[c] * vel_[st.node[c]];
          }
          if (impulses) {
            for (int c = 0; c < 8; ++c) dvi += st.N[c] * dvel_imp_[st.node[c]];
            a.work += P.mass[p] * dvi.dot(P.v[p] + 0.5 * dv);  // dvi . (v^{n-1/2} + v^{n+1/2}) / 2
          }
          P.v[p] += dv;
          P.x[p] += dt * vel;
          const auto mat = P.material[p];
          a.dt = std::min(a.dt, particle_step_bound(materials_[mat], lame_[mat][2], P.rho[p], P.stress[p], P.v[p], h));
          const bool ok = P.x[p].allFinite() && P.v[p].allFinite() && P.stress[p].allFinite() &&
                          std::isfinite(P.rho[p]) && grid_.contains(P.x[p]);
          if (!ok) a.bad = std::min(a.bad, p);
        }
        return a;
      },
      [](Acc a, const Acc& b) {
        a.work += b.work;
        a.dt = std::min(a.dt, b.dt);
        a.bad = std::min(a.bad, b.bad);
        return a;
      },
      tbb::simple_partitioner());
  impulse_work_ = acc.work;
  critical_dt_ = options_.cfl * acc.dt;
  if (acc.bad < n) check_particles(dt);
  time_ += dt;
  ++steps_;
}

void MpmSolver::check_particles(double dt) const {
  const auto& P = particles_;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!P.x[p].allFinite() || !P.v[p].allFinite() || !P.stress[p].allFinite() || !std::isfinite(P.rho[p])) {
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
}

void MpmSolver::step(double dt) {
  trial_step(dt);
  finish_step(dt);
}

MpmEnergies MpmSolver::energies() const {
  const auto& P = particles_;
  auto sum = [](MpmEnergies a, const MpmEnergies& b) {
    a.kinetic += b.kinetic;
    a.internal += b.internal;
    a.gravity += b.gravity;
    return a;
  };
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, P.size(), kGrain), MpmEnergies{},
      [&](const tbb::blocked_range<std::size_t>& r, MpmEnergies e) {
        for (std::size_t p = r.begin(); p != r.end(); ++p) {
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
      },
      sum, tbb::simple_partitioner());
}

Vec3 MpmSolver::total_momentum() const {
  Vec3 m = Vec3::Zero();
  for (std::size_t p = 0; p < particles_.size(); ++p) m += particles_.mass[p] * particles_.v[p];
  return m;
}

}  // namespace tetfsi::mpm
