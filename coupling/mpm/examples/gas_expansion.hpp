#pragma once
/// @file gas_expansion.hpp
/// Lian, Liu & Zhang (2014) section 7.3: a 0.9 x 1.9 block of ideal gas (Table 2: rho = 1,
/// gamma = 1.4, E0 = 25 so p0 = 10, viscosity 0.1) expands inside a 1 x 2 rectangular membrane
/// (rho = 0.5, E = 1e6, nu = 0.3, thickness 0.1), depth 0.1 along z. Quarter model (x, y >= 0)
/// with symmetry planes, particle spacing 0.025, cell and element size 0.1 (dimensionless units).
/// Reported: radii at 0 deg (x of the membrane node on y = 0) and 90 deg (y of the node on
/// x = 0), Fig. 16; energies, Fig. 18. Paper: settles to a circle of radius 0.96, ~5% energy lost.
#include <functional>

#include "coupling/mpm/examples/step_record.hpp"

namespace tetfsi::mpm_contact {

struct GasExpansionParams {
  double particle_spacing = 0.025;
  double cell = 0.1;     ///< grid cell and membrane element size
  double t_end = 3.0;
  double cfl = 0.9;      ///< on the smaller critical step (membrane)
  double gas_viscosity = 0.1;
  double hourglass = 0.1;
  ContactOptions contact{};
  int record_every = 50;  ///< steps between StepRecord callbacks
};

struct GasExpansionResult {
  double radius_0deg = 0, radius_90deg = 0;  ///< final radii
  double energy_initial = 0, energy_final = 0;
  double contact_dissipated = 0;  ///< accumulated work removed by the contact forces
  double energy_loss_fraction() const { return 1 - energy_final / energy_initial; }
  long steps = 0;
  long particle_updates = 0;  ///< particles x steps
  std::size_t particles = 0;
  int elements = 0;
};

/// Runs the example; `on_record` (optional) receives a StepRecord every `record_every` steps with
/// probes r_0deg, r_90deg, r_min, r_max (node radii about the axis).
/// @throws std::runtime_error on instability
GasExpansionResult run_gas_expansion(const GasExpansionParams& params,
                                     const std::function<void(const StepRecord&)>& on_record = nullptr);

}  // namespace tetfsi::mpm_contact
