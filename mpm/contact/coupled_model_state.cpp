/// @file coupled_model_state.cpp
/// CoupledModel::write_state / read_state and MpmMembraneCoupling's (coupled_model.hpp,
/// grid_contact.hpp) in a checkpoint (support/binary_stream.hpp).
#include "mpm/contact/coupled_model.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::mpm {

void MpmMembraneCoupling::write_state(BinaryWriter& out) const { out(contact_energy_, gap_); }

void MpmMembraneCoupling::read_state(BinaryReader& in) {
  const std::size_t nodes = gap_.size();
  in(contact_energy_, gap_);
  if (gap_.size() != nodes) in.fail("contact arrays of another grid");
}

void CoupledModel::write_state(BinaryWriter& out) const {
  mpm_.write_state(out);
  membrane_.write_state(out);
  coupling_.write_state(out);
  out(pending_, next_, balance0_, supplied_, injected_);
}

void CoupledModel::read_state(BinaryReader& in) {
  mpm_.read_state(in);
  membrane_.read_state(in);
  coupling_.read_state(in);
  in(pending_, next_, balance0_, supplied_, injected_);
  if (pending_.size() != sources_.size() || next_.size() != sources_.size()) in.fail("sources of another scene");
}

}  // namespace tetfsi::mpm
