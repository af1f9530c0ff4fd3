#pragma once
/// @file coupled_model.hpp
/// One MPM body set and one membrane in grid contact (Lian, Liu & Zhang 2014, section 6), advanced
/// one coupled step at a time, with optional gas sources that add particles (an airbag inflator)
/// and the divergence check of the `tetfsi run` mpm runner. Built from a scene by apps/mpm.
#include <cstdint>
#include <vector>

#include "mpm/contact/grid_contact.hpp"

namespace tetfsi::mpm {

/// Inflow of fluid particles: from t_start to t_end, mass enters at `mass_rate` [kg/s] as
/// particles of mass `particle_mass` placed in turn on `sites` (a lattice in the source region),
/// each with density `density`, internal energy `energy` per reference volume [J/m^3] and velocity
/// `velocity`. A particle is added once the mass due since the last one reaches particle_mass.
struct GasSource {
  std::uint16_t material = 0;
  std::vector<Vec3> sites;
  double particle_mass = 0, density = 0, energy = 0;
  Vec3 velocity = Vec3::Zero();
  double mass_rate = 0, t_start = 0, t_end = 0;
  /// Critical step of eq. (21) for the injected state, cfl h / (c + |v|) [s] (the solver's own bound is
  /// computed at the end of a step, before the particles of that step are added).
  double step_bound = 0;
};

/// Not copyable or movable (the coupling holds references to the bodies).
class CoupledModel {
 public:
  /// @param membrane_cfl safety factor on the membrane's critical step (eq. 48)
  CoupledModel(mpm::MpmSolver mpm, mpm::Membrane membrane, ContactOptions contact, double membrane_cfl,
               std::vector<GasSource> sources = {});
  CoupledModel(const CoupledModel&) = delete;
  CoupledModel& operator=(const CoupledModel&) = delete;

  const mpm::MpmSolver& mpm() const { return mpm_; }
  const mpm::Membrane& membrane() const { return membrane_; }
  const MpmMembraneCoupling& coupling() const { return coupling_; }

  /// Largest stable step now [s]: min(MPM eq. 21 with its cfl, membrane_cfl x eq. 48, the sources'
  /// step bounds while they run).
  double max_dt() const;
  /// One coupled step of section 6, then the particles the sources owe by the new time.
  /// @throws std::runtime_error on non-finite states or a particle leaving the grid
  ContactReport step(double dt);
  /// Checkpoints (coupled_model_state.cpp): particles, grid, membrane, contact and the sources'
  /// bookkeeping, bit for bit; read into a model made from the same scene. @throws BinaryReadError
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);
  /// Energy carried in by the sources so far (internal E m / rho0 + kinetic) [J].
  double injected_energy() const { return injected_; }
  /// Kinetic + internal + gravity of the particles, kinetic + strain + hourglass of the membrane [J].
  static double stored_energy(const CoupledEnergies& e) {
    return e.mpm.total() + e.membrane.kinetic + e.membrane.strain + e.membrane.hourglass;
  }
  double stored_energy() const { return stored_energy(coupling_.energies()); }
  /// CoupledEnergies::balance minus the injected energy: constant for an exactly conservative scheme.
  double balance(const CoupledEnergies& e) const { return e.balance() - injected_; }
  /// Divergence check for a state that is still finite: an explicit step past its stable limit
  /// grows exponentially, so the energy balance soon exceeds all the energy ever put in.
  /// @throws std::runtime_error if balance - balance(t = 0) exceeds the energy supplied: the
  ///         kinetic, internal, strain and hourglass energy at t = 0 (not the gravity potential,
  ///         which depends on the origin), the sum of |work| of the membrane's external loads over
  ///         the steps and the injected energy; the message names the time and both figures
  void check_energy_growth(const CoupledEnergies& e) const;
  void check_energy_growth() const { check_energy_growth(coupling_.energies()); }

 private:
  void inject(double t0, double t1);

  mpm::MpmSolver mpm_;
  mpm::Membrane membrane_;
  MpmMembraneCoupling coupling_;
  double membrane_cfl_;
  std::vector<GasSource> sources_;
  std::vector<double> pending_;     // per source: mass due and not yet added [kg]
  std::vector<std::size_t> next_;   // per source: next site
  double balance0_ = 0;  // at construction (t = 0)
  double supplied_ = 0;  // see check_energy_growth
  double injected_ = 0;
};

}  // namespace tetfsi::mpm
