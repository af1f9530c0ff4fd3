#include "coupling/mpm/examples/example_model.hpp"

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

}  // namespace tetfsi::mpm_contact
