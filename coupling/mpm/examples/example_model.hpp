#pragma once
/// @file example_model.hpp
/// A paper example (Lian, Liu & Zhang 2014, section 7) as a model that is advanced one coupled
/// step at a time, for callers that own the time loop (the `tetfsi run` mpm runner). The
/// callback drivers run_gas_expansion / run_sphere_membrane are loops over this model.
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "coupling/mpm/examples/step_record.hpp"
#include "coupling/mpm/grid_contact.hpp"

namespace tetfsi::mpm_contact {

struct GasExpansionParams;
struct SphereMembraneParams;

/// The two bodies, their grid contact and the example's probes. Not copyable or movable (the
/// coupling holds references to the bodies).
class ExampleModel {
 public:
  using Probes = std::vector<std::pair<std::string, double>>;

  /// @param dt_factor the step is dt_factor x the coupled critical step (section 4.4)
  ExampleModel(mpm::MpmSolver mpm, membrane::Membrane membrane, ContactOptions contact, double dt_factor)
      : mpm_(std::move(mpm)), membrane_(std::move(membrane)), coupling_(mpm_, membrane_, contact),
        dt_factor_(dt_factor) {
    const auto e = coupling_.energies();
    balance0_ = e.balance();
    supplied_ = e.mpm.kinetic + e.mpm.internal + e.membrane.kinetic + e.membrane.strain + e.membrane.hourglass;
  }
  ExampleModel(const ExampleModel&) = delete;
  ExampleModel& operator=(const ExampleModel&) = delete;

  const mpm::MpmSolver& mpm() const { return mpm_; }
  const membrane::Membrane& membrane() const { return membrane_; }
  const MpmMembraneCoupling& coupling() const { return coupling_; }

  /// Largest stable step now [s]: dt_factor x min(MPM eq. 21, membrane critical step).
  double max_dt() const { return dt_factor_ * coupling_.critical_time_step(); }
  /// One coupled step of section 6. @throws std::runtime_error on non-finite states
  ContactReport step(double dt) {
    const double work_before = membrane_.external_work();
    ContactReport rep = coupling_.step(dt);
    supplied_ += std::abs(membrane_.external_work() - work_before);
    return rep;
  }
  /// Named probes of the example (see gas_expansion.hpp, sphere_membrane.hpp).
  Probes probes() const { return probes_ ? probes_() : Probes{}; }
  /// Kinetic + internal + gravity of the particles, kinetic + strain + hourglass of the membrane [J].
  double stored_energy() const { return stored_energy(coupling_.energies()); }
  /// The same from energies `e` already at hand (coupling().energies()).
  static double stored_energy(const CoupledEnergies& e) {
    return e.mpm.total() + e.membrane.kinetic + e.membrane.strain + e.membrane.hourglass;
  }
  /// Divergence check for a state that is still finite: an explicit step past its stable limit
  /// grows exponentially, so the energy balance (CoupledEnergies::balance, constant for an exact
  /// scheme; the contact only removes energy) soon exceeds all the energy ever put in.
  /// @throws std::runtime_error if balance - balance(t = 0) exceeds the energy supplied: the
  ///         kinetic, internal, strain and hourglass energy at t = 0 (not the gravity potential,
  ///         which depends on the origin) plus the sum of |work| of the membrane's external loads
  ///         over the steps taken through step(); the message names the time and both figures
  void check_energy_growth() const { check_energy_growth(coupling_.energies()); }
  /// The same with the current energies `e` already at hand (coupling().energies()).
  void check_energy_growth(const CoupledEnergies& e) const;
  /// A StepRecord of the current state (bodies valid while this model lives).
  StepRecord record(long step, double time, double dt, int contact_nodes) const;

  void set_probes(std::function<Probes()> probes) { probes_ = std::move(probes); }

 private:
  mpm::MpmSolver mpm_;
  membrane::Membrane membrane_;
  MpmMembraneCoupling coupling_;
  double dt_factor_;
  double balance0_ = 0;  // at construction (t = 0)
  double supplied_ = 0;  // see check_energy_growth
  std::function<Probes()> probes_;
};

/// Section 7.3 set up as in run_gas_expansion. @throws std::invalid_argument on bad sizes
std::unique_ptr<ExampleModel> make_gas_expansion(const GasExpansionParams& params);
/// Sections 7.1 / 7.2 set up as in run_sphere_membrane. @throws std::invalid_argument on bad sizes
std::unique_ptr<ExampleModel> make_sphere_membrane(const SphereMembraneParams& params);

}  // namespace tetfsi::mpm_contact
