#pragma once
/// @file watchdog.hpp
/// The physics watchdog of the tet-solid runners (/simulation/watchdog): inverted tets of a
/// deforming solid, and (solid-only scenes) total energy rising above its start. Each check
/// returns "" or a diagnosis naming the solid and the keys to change; the driver adds the step.
#include <string>

#include <Eigen/Core>

#include "apps/scene/scene.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::run {

struct WatchdogSettings {
  bool allow_inverted = false;     ///< /simulation/watchdog/allow_inverted
  double max_energy_growth = 0.5;  ///< /simulation/watchdog/max_energy_growth
};

/// The resolved /simulation/watchdog block.
WatchdogSettings watchdog_settings(const scene::Json& simulation);

/// "" if no tet of `model` is inverted at displacement `d` (volume ratio J = V / V0 <= 0), else
/// the diagnosis for solid `name` (/solids/`index`).
std::string inverted_tets(const solid::TetModel& model, const Eigen::VectorXd& d, const std::string& name,
                          int index, const WatchdogSettings& settings);

/// Energy balance of one solid whose loads are all conservative (gravity, springs, static
/// obstacles with friction, fixed nodes): its total energy E = kinetic + strain + gravitational +
/// spring can only fall (damping, dissipative integration, friction). Energy from nowhere is a
/// rise E - E_0 > max_energy_growth * S, with the scale S the largest kinetic + strain + spring
/// energy so far, at least m |g| L (mass m, rest size L: the work of lifting it by its size).
class EnergyWatch {
 public:
  EnergyWatch() = default;
  /// @param total  E_0 [J]; @param floor  m |g| L [J] (> 0 or a small positive number)
  EnergyWatch(double total, double mechanical, double floor) : start_(total), scale_(std::max(mechanical, floor)) {}
  /// Records the energies after a step.
  void record(double total, double mechanical) {
    last_ = total;
    scale_ = std::max(scale_, mechanical);
  }
  /// "" or the diagnosis for solid `name` (/solids/`index`, integrator `scheme`).
  std::string check(const std::string& name, int index, const std::string& scheme,
                    const WatchdogSettings& settings) const;

 private:
  double start_ = 0, last_ = 0, scale_ = 0;
};

}  // namespace tetfsi::run
