#include "coupling/mpm/examples/step_record.hpp"

#include <cstdio>

namespace tetfsi::mpm_contact {

std::string csv_header(const StepRecord& r) {
  std::string h =
      "step,time,dt,contact_nodes,kinetic_mpm,internal_mpm,gravity_mpm,kinetic_membrane,strain_membrane,"
      "hourglass_membrane,external_work_membrane,contact_dissipation,energy_balance";
  for (const auto& [name, value] : r.probes) h += "," + name;
  return h;
}

std::string csv_row(const StepRecord& r) {
  char buf[512];
  const auto& e = r.energies;
  std::snprintf(buf, sizeof buf, "%ld,%.9g,%.6g,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", r.step, r.time, r.dt,
                r.contact_nodes, e.mpm.kinetic, e.mpm.internal, e.mpm.gravity, e.membrane.kinetic, e.membrane.strain,
                e.membrane.hourglass, e.membrane.external_work, e.contact, e.balance());
  std::string s = buf;
  for (const auto& [name, value] : r.probes) {
    std::snprintf(buf, sizeof buf, ",%.9g", value);
    s += buf;
  }
  return s;
}

}  // namespace tetfsi::mpm_contact
