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

std::string inverted_hexes(const solid::hex::HexModel& model, const Eigen::VectorXd& d, const std::string& name,
                           int index) {
  const std::vector<int> failed = model.failed_elements(d);
  if (failed.empty()) return "";
  const int e = failed.front();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int a : model.mesh().hexes[e]) centre += model.mesh().vertices[a] / 8.0;
  return fmt::format("hex solid '{}': {} of {} elements inverted (det F <= 0 at a Gauss point), the first element {} "
                     "(rest centre ({:.4g}, {:.4g}, {:.4g}) m): the step is too large for the material or the loads "
                     "too strong for it. Lower /simulation/dt, stiffen /solids/{}/material/youngs_modulus (now {:g} Pa) "
                     "or lighten the loads (/simulation/gravity, /solids/{}/boundary_conditions); an inverted hex8 "
                     "element has no internal force, so the run cannot go on",
                     name, failed.size(), model.mesh().num_hexes(), e, centre.x(), centre.y(), centre.z(), index,
                     model.material().youngs_modulus, index);
}

std::string EnergyWatch::diagnosis(const std::string& subject, const std::string& terms, const std::string& why,
                                   const std::string& advice, const WatchdogSettings& settings) const {
  if (!exceeded(settings)) return "";
  const double rise = last_ - start_;
  return fmt::format("{}: the total energy ({}) rose by {:.3g} J above its start ({:.3g} J), {:.3g} times its energy "
                     "scale of {:.3g} J, while {}: energy from nowhere, the integration is unstable. {}, or raise "
                     "/simulation/watchdog/max_energy_growth (now {:g})",
                     subject, terms, rise, start_, rise / scale_, scale_, why, advice, settings.max_energy_growth);
}

std::string EnergyWatch::check(const std::string& name, int index, const std::string& scheme,
                               const WatchdogSettings& settings) const {
  return diagnosis(fmt::format("solid '{}'", name), "kinetic + strain + gravitational + springs",
                   "every load on it is conservative",
                   "Lower /simulation/dt" +
                       (scheme == "trapezoidal"
                            ? fmt::format(", use /solids/{}/integrator/scheme \"chentanez\" (dissipative)", index)
                            : fmt::format(" or soften /solids/{}/material (a stiff body needs a short step)", index)),
                   settings);
}

double energy_floor(const Eigen::VectorXd& X, double weight) {
  const Eigen::Map<const Eigen::Matrix3Xd> P(X.data(), 3, X.size() / 3);
  const double size = (P.rowwise().maxCoeff() - P.rowwise().minCoeff()).norm();
  return std::max(weight * size, 1e-12);
}

std::string coupled_energy_source(const scene::Json& js) {
  if (js.contains("domain")) {
    const auto& d = js["domain"];
    if (d.contains("inflows") && !d["inflows"].empty()) return "/domain/inflows push fluid in";
    if (d.contains("open_faces") && !d["open_faces"].empty())
      return "/domain/open_faces let fluid in and out (gravity can drain the tank)";
    if (d.contains("open_patches") && !d["open_patches"].empty())
      return "/domain/open_patches let fluid in and out (gravity can drain the tank)";
  }
  if (js.contains("emitters") && !js["emitters"].empty()) return "/emitters add fluid, smoke or heat (buoyancy)";
  const auto& f = js.at("fluid");
  if (f.value("vorticity_confinement", 0.0) > 0) return "/fluid/vorticity_confinement adds rotation";
  if (js.contains("solids"))
    for (std::size_t i = 0; i < js["solids"].size(); ++i) {
      if (js["solids"][i].contains("motion") && js["solids"][i]["motion"].value("type", "none") != "none")
        return fmt::format("/solids/{}/motion moves the solid as prescribed", i);
      for (std::size_t r = 0; r < js["solids"][i].value("fixed_regions", scene::Json::array()).size(); ++r) {
        const auto& v = js["solids"][i]["fixed_regions"][r].value("velocity", scene::Json::array({0, 0, 0}));
        if (v != scene::Json::array({0, 0, 0}))
          return fmt::format("/solids/{}/fixed_regions/{}/velocity drives the solid", i, r);
      }
    }
  return "";
}

}  // namespace tetfsi::run
