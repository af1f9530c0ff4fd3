/// @file mpm_solver.cpp
/// MpmSolver set-up, the whole step, the particle checks and the energy and momentum sums.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "fluid/mpm/mpm_solver.hpp"
#include "fluid/mpm/reduce.hpp"
#include "fluid/mpm/solver_detail.hpp"

namespace tetfsi::mpm {
using namespace detail;

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
  // The message is formatted only for a bad particle (formatting every particle's position was a
  // quarter of the set-up of a 113k-particle body).
  auto where = [&](std::size_t p) {
    std::ostringstream s;
    s << "MpmSolver: particle " << p << " at (" << particles_.x[p].transpose() << ")";
    return s.str();
  };
  for (std::size_t p = 0; p < n; ++p) {
    if (particles_.material[p] >= materials_.size())
      throw std::invalid_argument(where(p) + " has material index out of range");
    if (!(particles_.mass[p] > 0) || !(particles_.rho[p] > 0))
      throw std::invalid_argument(where(p) + " has non-positive mass or density");
    if (!grid_.contains(particles_.x[p])) throw std::invalid_argument(where(p) + " is outside the grid");
    const Mat3& sg = particles_.stress[p];  // the stress update keeps sigma symmetric; it must start so
    if (sg(0, 1) != sg(1, 0) || sg(0, 2) != sg(2, 0) || sg(1, 2) != sg(2, 1))
      throw std::invalid_argument(where(p) + " has a non-symmetric stress");
    total_mass += particles_.mass[p];
  }
  for (const auto& m : materials_)
    lame_.push_back({m.lame_lambda(), 2.0 * m.shear_modulus(), m.lame_lambda() + 2 * m.shear_modulus()});
  for (const auto& m : materials_) inv_rho0_.push_back(1.0 / m.rho0);
  for (std::size_t m = 0; m < materials_.size(); ++m) {
    elastic_.push_back(materials_[m].kind == Material::Kind::LinearElastic);
    inv_p_modulus_.push_back(elastic_.back() ? 1.0 / lame_[m][2] : 0.0);
  }
  mask_ = grid_.build_constraint_mask();
  const auto nn = static_cast<std::size_t>(grid_.num_nodes());
  mass_.assign(nn, 0.0);
  for (auto* f : {&mom_old_, &mom_new_, &force_, &impulse_, &vel_, &dvel_, &dvel_imp_})
    f->assign(nn, Vec3::Zero());
  mass_eps_ = n ? 1e-12 * total_mass / double(n) : 0.0;
  critical_h_ = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < n; ++p)
    critical_h_ = std::min(critical_h_, particle_step_bound(materials_[particles_.material[p]],
                                                              lame_[particles_.material[p]][2], particles_.rho[p],
                                                              particles_.stress[p], particles_.v[p], grid_.dx));
  critical_h_ *= options_.cfl;
}


void MpmSolver::check_particles(double h) const {
  const auto& P = particles_;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!P.x[p].allFinite() || !P.v[p].allFinite() || !P.stress[p].allFinite() || !std::isfinite(P.rho[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " became non-finite at step " << steps_ + 1 << " (t = " << time_ + h
          << "); the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
    if (!grid_.contains(P.x[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " left the background grid at (" << P.x[p].transpose()
          << ") at t = " << time_ + h;
      throw std::runtime_error(msg.str());
    }
    if (!(P.rho[p] > 0)) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " has a non-positive density " << P.rho[p] << " at t = " << time_ + h
          << "; the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
  }
}

void MpmSolver::step(double h) {
  trial_step(h);
  finish_step(h);
}

MpmEnergies MpmSolver::energies() const {
  const auto& P = particles_;
  auto sum = [](MpmEnergies a, const MpmEnergies& b) {
    a.kinetic += b.kinetic;
    a.internal += b.internal;
    a.gravity += b.gravity;
    return a;
  };
  return deterministic_reduce(
      P.size(), kGrain, kSerialBelow, MpmEnergies{},
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
      sum);
}

Vec3 MpmSolver::total_momentum() const {
  Vec3 m = Vec3::Zero();
  for (std::size_t p = 0; p < particles_.size(); ++p) m += particles_.mass[p] * particles_.v[p];
  return m;
}


}  // namespace tetfsi::mpm
