#pragma once
/// @file fluid_columns.hpp
/// The stats.csv phases and columns that a fluid's models add, shared by the fluid and coupled
/// runners: a free surface (phase `surface`, second; columns `liquid_volume`, `volume_drift`),
/// viscosity (phase `viscosity`; column `viscous_iterations`) and velocity on particles (phase
/// `particles`: their motion, reseeding, P2G and G2P; column `particles`, their count).
#include <string>
#include <vector>

#include "fluid/fluid_solver.hpp"

namespace tetfsi::run {

/// Adds the phases of `fluid`'s models to the runner's own (`surface` after the first).
void add_fluid_phases(const fluid::FluidSolver& fluid, std::vector<std::string>& phases);
/// Appends the columns of `fluid`'s models.
void add_fluid_columns(const fluid::FluidSolver& fluid, std::vector<std::string>& columns);
/// The step `s`'s values of those phases and columns, in the same places.
void add_fluid_values(const fluid::FluidSolver& fluid, const fluid::StepReport& s, std::vector<double>& phase_seconds,
                      std::vector<double>& values);

}  // namespace tetfsi::run
