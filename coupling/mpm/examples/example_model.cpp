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

void ExampleModel::check_energy_growth() const {
  const auto e = coupling_.energies();
  const double gain = e.balance() - balance0_, supplied = std::abs(stored0_) + std::abs(e.membrane.external_work);
  if (gain > supplied) {
    std::ostringstream msg;
    msg << "the energy balance grew by " << gain << " J by t = " << coupling_.time() << " s, more than the " << supplied
        << " J of the initial state and the external work together (the step is probably above the critical step)";
    throw std::runtime_error(msg.str());
  }
}

}  // namespace tetfsi::mpm_contact
