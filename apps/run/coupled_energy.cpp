#include "apps/run/coupled_energy.hpp"

#include <fmt/format.h>

#include "apps/run/scene_values.hpp"
#include "solid/integrator/newmark.hpp"

namespace tetfsi::run {

EnergyWatch coupled_energy_watch(coupling::CoupledStepper& stepper, const scene::Json& scene) {
  fluid::StepReport f;
  stepper.fluid().report_energies(f);
  double total = f.kinetic_energy + f.gravity_potential, mechanical = f.kinetic_energy, floor = 0;
  const double g = vec3(scene.at("simulation").at("gravity")).norm();
  for (int i = 0; i < stepper.num_solids(); ++i) {
    const solid::StepStats e = stepper.solid(i).energies();
    total += e.total();
    mechanical += e.kinetic + e.strain + e.spring;
    const auto& model = stepper.solid_model(i);
    floor += energy_floor(model.reference_positions(), model.lumped_masses().sum() * g);
  }
  // A free surface is resolved to about a cell: the level set may move it by up to an edge
  // length h, changing the liquid's potential by up to rho V |g| h (measured on dam_break_ci:
  // +10 J of its 289 J in the first 0.1 s, with rho V |g| h = 75 J).
  if (stepper.fluid().has_free_surface())
    floor += stepper.fluid().params().density * stepper.fluid().liquid().total_volume() * g *
             scene.at("mesh").at("edge_length").get<double>();
  return EnergyWatch(total, mechanical, floor);
}

std::string coupled_energy_diagnosis(coupling::CoupledStepper& stepper, const EnergyWatch& energy,
                                   const std::vector<std::string>& names, const std::string& scheme,
                                   const WatchdogSettings& settings) {
  int fastest = 0;
  double most = -1;
  for (int i = 0; i < stepper.num_solids(); ++i) {
    const Eigen::VectorXd& u = stepper.solid(i).velocity();
    const Eigen::VectorXd& m = stepper.solid_model(i).lumped_masses();
    double k = 0;
    for (int a = 0; a < m.size(); ++a) k += 0.5 * m[a] * u.segment<3>(3 * a).squaredNorm();
    if (k > most) most = k, fastest = i;
  }
  const auto& mat = stepper.solid_model(fastest).material();
  const double rho_f = stepper.fluid().params().density;
  std::string advice = "Lower /simulation/dt";
  if (scheme == "time_splitting")
    advice += fmt::format(", use /coupling/scheme \"simultaneous\" (time splitting is unstable when the fluid a "
                          "solid moves outweighs it, the added-mass instability: solid '{}' has {:g} kg/m^3 in a "
                          "fluid of {:g} kg/m^3)", names[fastest], mat.density, rho_f);
  advice += fmt::format(" or change the material of solid '{}' (/solids/{}/material: density {:g} kg/m^3, "
                        "youngs_modulus {:g} Pa; a stiff body needs a short step)",
                        names[fastest], fastest, mat.density, mat.youngs_modulus);
  return energy.diagnosis(fmt::format("fluid and solids ({} coupling)", scheme),
                           "fluid kinetic + fluid gravitational + solid kinetic, strain, springs and gravitational",
                           "the container is closed and every load is conservative (walls, gravity; no inflow, "
                           "open face or emitter)",
                           advice, settings);
}

}  // namespace tetfsi::run
