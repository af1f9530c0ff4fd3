#include "apps/run/fluid_columns.hpp"

namespace tetfsi::run {

void add_fluid_phases(const fluid::FluidSolver& fluid, std::vector<std::string>& phases) {
  if (fluid.has_free_surface()) phases.insert(phases.begin() + 1, "surface");
  if (fluid.viscous()) phases.push_back("viscosity");
  if (fluid.params().particles.enabled()) phases.push_back("particles");
}

void add_fluid_columns(const fluid::FluidSolver& fluid, std::vector<std::string>& columns) {
  if (fluid.has_free_surface()) columns.insert(columns.end(), {"liquid_volume", "volume_drift"});
  if (fluid.viscous()) columns.push_back("viscous_iterations");
  if (fluid.params().particles.enabled()) columns.push_back("particles");
}

void add_fluid_values(const fluid::FluidSolver& fluid, const fluid::StepReport& s, std::vector<double>& phase_seconds,
                      std::vector<double>& values) {
  if (fluid.has_free_surface()) {
    phase_seconds.insert(phase_seconds.begin() + 1, s.surface_seconds);
    values.insert(values.end(), {s.liquid_volume, s.volume_drift});
  }
  if (fluid.viscous()) {
    phase_seconds.push_back(s.viscosity_seconds);
    values.push_back(double(s.viscous_iterations));
  }
  if (fluid.params().particles.enabled()) {
    phase_seconds.push_back(s.particle_seconds);
    values.push_back(double(s.num_particles));
  }
}

}  // namespace tetfsi::run
