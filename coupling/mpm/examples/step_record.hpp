#pragma once
/// @file step_record.hpp
/// Per-step probes of the MPM-membrane examples (one row of stats.csv).
#include <Eigen/Core>

#include <string>
#include <vector>

#include "coupling/mpm/grid_contact.hpp"

namespace tetfsi::mpm_contact {

struct StepRecord {
  long step = 0;
  double time = 0;  ///< [s]
  double dt = 0;    ///< [s]
  int contact_nodes = 0;
  CoupledEnergies energies;
  /// The bodies at this instant (valid during the callback only), e.g. for writing frames:
  /// particles as a point cloud, membrane quads as VtkCell::Quad.
  const mpm::MpmSolver* mpm = nullptr;
  const membrane::Membrane* membrane = nullptr;
  /// Named probe values of the example (tracked z of points, radii, ...), see each example.
  std::vector<std::pair<std::string, double>> probes;
};

/// CSV header and row: step,time,dt,contact_nodes,kinetic_mpm,internal_mpm,kinetic_membrane,
/// strain_membrane,hourglass_membrane,external_work,contact,total,<probes...>.
std::string csv_header(const StepRecord& r);
std::string csv_row(const StepRecord& r);

}  // namespace tetfsi::mpm_contact
