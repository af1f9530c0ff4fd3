#pragma once
/// @file coupled_energy.hpp
/// The coupled runner's energy watchdog (watchdog.hpp): the balance of a closed container,
///   E = fluid kinetic + fluid gravitational + Σ_solids (kinetic + strain + springs + gravitational),
/// started at the initial state with the scale max(mechanical energy, Σ m|g|L + ρ V |g| h), and
/// the diagnosis that names the solid moving most and the keys to change.
#include <string>
#include <vector>

#include "apps/run/watchdog.hpp"
#include "apps/scene/schema.hpp"
#include "coupling/coupled_stepper.hpp"

namespace tetfsi::run {

/// The balance at the stepper's current (initial) state. Σ m|g|L over the solids is the floor of
/// the scale; a free surface adds ρ V |g| h (h = mesh.edge_length): the level set may move the
/// surface by up to a cell (measured on dam_break_ci: +10 J of 289 J in the first 0.1 s, with
/// ρ V |g| h = 75 J).
EnergyWatch coupled_energy_watch(coupling::CoupledStepper& stepper, const scene::Json& scene);

/// The diagnosis when `energy` exceeded the limit: names the solid with the largest kinetic
/// energy and advises a smaller step, the simultaneous scheme (for time splitting) or its material.
std::string coupled_energy_diagnosis(coupling::CoupledStepper& stepper, const EnergyWatch& energy,
                                     const std::vector<std::string>& names, const std::string& scheme,
                                     const WatchdogSettings& settings);

}  // namespace tetfsi::run
