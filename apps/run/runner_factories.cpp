// create_simulation (simulation.hpp): each runner's factory, in a file of its own so that the
// registry (runners.cpp) links none of the runners.
#include <stdexcept>

#include "apps/run/simulation.hpp"

namespace tetfsi::run {

std::unique_ptr<Simulation> make_coupled_runner();
std::unique_ptr<Simulation> make_fluid_runner();
std::unique_ptr<Simulation> make_kinematic_runner();
std::unique_ptr<Simulation> make_solid_runner();
std::unique_ptr<Simulation> make_hex_runner();
std::unique_ptr<Simulation> make_mpm_runner();
std::unique_ptr<Simulation> make_mesh_only_runner();

std::unique_ptr<Simulation> create_simulation(const RunnerEntry& runner) {
  const std::string& n = runner.name;
  if (n == "coupled") return make_coupled_runner();
  if (n == "fluid") return make_fluid_runner();
  if (n == "kinematic") return make_kinematic_runner();
  if (n == "solid") return make_solid_runner();
  if (n == "hex") return make_hex_runner();
  if (n == "mpm") return make_mpm_runner();
  if (n == "mesh_only") return make_mesh_only_runner();
  throw std::logic_error("create_simulation: no runner named " + n);
}

}  // namespace tetfsi::run
