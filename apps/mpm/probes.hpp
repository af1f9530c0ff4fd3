#pragma once
/// @file probes.hpp
/// The probes of an mpm scene (the `probes` block kinds membrane_point, membrane_radius,
/// membrane_volume, particle_point, body_energy, total_energy), resolved against the setup at
/// t = 0 (which node, which particle, which body) and evaluated on the running model.
#include <string>
#include <vector>

#include "apps/mpm/setup.hpp"

namespace tetfsi::mpm_setup {

struct Probe {
  enum class Kind { MembranePoint, MembraneRadius, MembraneVolume, ParticlePoint, BodyEnergy, TotalEnergy };
  Kind kind = Kind::TotalEnergy;
  int node = -1;              ///< membrane_point: the node nearest to `point` at t = 0
  std::size_t particle = 0;   ///< particle_point: the body's particle nearest to `point` at t = 0
  Vec3 rest = Vec3::Zero();   ///< its position at t = 0
  int axis = -1;              ///< x, y, z of the position (or displacement); -1: |displacement|
  bool displacement = false;  ///< displacement from `rest` instead of position
  Vec3 center = Vec3::Zero(), direction = Vec3::UnitZ();  ///< membrane_radius: the axis
  bool max = false;           ///< membrane_radius: max (else min) over the nodes
  int body = -1;              ///< body_energy: body index, -1 for the membrane
  std::string energy;         ///< body_energy: kinetic, internal or total
};

/// @throws SetupError naming /probes/i/... (unknown body, membrane_volume of an open membrane)
std::vector<Probe> resolve_probes(const Setup& setup, const Json& probes);

/// The value of a probe now.
double evaluate(const Probe& p, const Setup& setup, const mpm_contact::CoupledModel& model);

/// Kinetic, internal (fluid E V0, solid strain energy) energy of the particles of `material` [J].
void body_energies(const mpm::MpmSolver& mpm, std::uint16_t material, double& kinetic, double& internal);

}  // namespace tetfsi::mpm_setup
