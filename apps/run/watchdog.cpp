#include "apps/run/watchdog.hpp"

#include <fmt/format.h>

namespace tetfsi::run {

WatchdogSettings watchdog_settings(const scene::Json& simulation) {
  WatchdogSettings s;
  const auto& w = simulation.at("watchdog");
  s.allow_inverted = w.at("allow_inverted").get<bool>();
  s.max_energy_growth = w.at("max_energy_growth").get<double>();
  return s;
}

std::string inverted_tets(const solid::TetModel& model, const Eigen::VectorXd& d, const std::string& name,
                          int index, const WatchdogSettings& settings) {
  if (settings.allow_inverted) return "";
  const Eigen::VectorXd J = model.volume_ratios(d);
  if (!J.allFinite())
    return fmt::format("solid '{}': the deformation overflowed (a tet volume is not finite): the loads are far too "
                       "strong for the material. Check /simulation/gravity and the loads, or stiffen "
                       "/solids/{}/material/youngs_modulus (now {:g} Pa)", name, index, model.material().youngs_modulus);
  const auto inverted = (J.array() <= 0.0).count();
  if (inverted == 0) return "";
  return fmt::format("solid '{}': {} of {} tets inverted (volume ratio down to {:.3g}): the step is too large for "
                     "the material or the loads too strong for it. Lower /simulation/dt, stiffen "
                     "/solids/{}/material/youngs_modulus (now {:g} Pa) or lighten the loads (/simulation/gravity); "
                     "/simulation/watchdog/allow_inverted lets the run continue",
                     name, inverted, J.size(), J.minCoeff(), index, model.material().youngs_modulus);
}

std::string EnergyWatch::check(const std::string& name, int index, const std::string& scheme,
                               const WatchdogSettings& settings) const {
  const double rise = last_ - start_;
  if (!(rise > settings.max_energy_growth * scale_)) return "";
  return fmt::format("solid '{}': the total energy (kinetic + strain + gravitational + springs) rose by {:.3g} J "
                     "above its start ({:.3g} J), {:.3g} times its energy scale of {:.3g} J, while every load on it "
                     "is conservative: energy from nowhere, the integration is unstable. Lower /simulation/dt{}, or "
                     "raise /simulation/watchdog/max_energy_growth (now {:g})",
                     name, rise, start_, rise / scale_, scale_,
                     scheme == "trapezoidal" ? fmt::format(", use /solids/{}/integrator/scheme \"chentanez\" (dissipative)", index)
                                             : fmt::format(" or soften /solids/{}/material (a stiff body needs a short step)", index),
                     settings.max_energy_growth);
}

}  // namespace tetfsi::run
