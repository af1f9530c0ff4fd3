#include "coupling/mpm/examples/example_model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tetfsi::mpm_contact {

StepRecord ExampleModel::record(long step, double time, double dt, int contact_nodes) const {
  StepRecord r;
  r.step = step;
  r.time = time;
  r.dt = dt;
  r.contact_nodes = contact_nodes;
  r.mpm = &mpm_;
  r.membrane = &membrane_;
  r.energies = coupling_.energies();
  r.probes = probes();
  return r;
}

void ExampleModel::check_energy_growth(const CoupledEnergies& e) const {
  const double gain = e.balance() - balance0_;
  if (gain > supplied_) {
    std::ostringstream msg;  // energies in J, or in the gas example's dimensionless units
    msg << "the energy balance grew by " << gain << " by t = " << coupling_.time() << ", more than the " << supplied_
        << " of the initial state and the external work together (the step is probably above the critical step)";
    throw std::runtime_error(msg.str());
  }
}

}  // namespace tetfsi::mpm_contact
