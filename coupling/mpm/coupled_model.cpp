#include "coupling/mpm/coupled_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tetfsi::mpm_contact {

CoupledModel::CoupledModel(mpm::MpmSolver mpm, membrane::Membrane membrane, ContactOptions contact,
                           double membrane_cfl, std::vector<GasSource> sources)
    : mpm_(std::move(mpm)), membrane_(std::move(membrane)), coupling_(mpm_, membrane_, contact),
      membrane_cfl_(membrane_cfl), sources_(std::move(sources)), pending_(sources_.size(), 0.0),
      next_(sources_.size(), 0) {
  for (const auto& s : sources_)
    if (s.sites.empty() || !(s.particle_mass > 0) || !(s.mass_rate >= 0) || !(s.step_bound > 0))
      throw std::invalid_argument("gas source: needs sites, a positive particle mass and step bound");
  const auto e = coupling_.energies();
  balance0_ = e.balance();
  supplied_ = e.mpm.kinetic + e.mpm.internal + e.membrane.kinetic + e.membrane.strain + e.membrane.hourglass;
}

double CoupledModel::max_dt() const {
  double dt = std::min(mpm_.critical_time_step(), membrane_.critical_time_step(membrane_cfl_));
  const double t = coupling_.time();
  for (const auto& s : sources_)
    if (t < s.t_end) dt = std::min(dt, s.step_bound);
  return dt;
}

ContactReport CoupledModel::step(double dt) {
  const double work_before = membrane_.external_work(), t0 = coupling_.time();
  ContactReport rep = coupling_.step(dt);
  supplied_ += std::abs(membrane_.external_work() - work_before);
  if (!sources_.empty()) inject(t0, coupling_.time());
  return rep;
}

void CoupledModel::inject(double t0, double t1) {
  mpm::Particles* P = nullptr;  // write access only when a particle is added (it re-bins)
  for (std::size_t k = 0; k < sources_.size(); ++k) {
    const auto& s = sources_[k];
    const double a = std::max(t0, s.t_start), b = std::min(t1, s.t_end);
    if (b <= a) continue;
    pending_[k] += s.mass_rate * (b - a);
    while (pending_[k] >= s.particle_mass) {
      if (!P) P = &mpm_.particles();
      const Vec3& x = s.sites[next_[k]++ % s.sites.size()];
      P->add(s.particle_mass, x, s.velocity, s.density, s.energy, s.material);
      P->stress.back() = -mpm_.materials()[s.material].pressure(s.density, s.energy) * mpm::Mat3::Identity();
      pending_[k] -= s.particle_mass;
      const double rho0 = mpm_.materials()[s.material].rho0;
      const double e = s.energy * s.particle_mass / rho0 + 0.5 * s.particle_mass * s.velocity.squaredNorm();
      injected_ += e;
      supplied_ += e;
    }
  }
}

void CoupledModel::check_energy_growth(const CoupledEnergies& e) const {
  const double gain = balance(e) - balance0_;
  if (gain > supplied_) {
    std::ostringstream msg;
    msg << "the energy balance grew by " << gain << " by t = " << coupling_.time() << ", more than the "
        << supplied_ << " of the initial state, the external work and the sources together (the step is "
        << "probably above the critical step)";
    throw std::runtime_error(msg.str());
  }
}

}  // namespace tetfsi::mpm_contact
