/// @file membrane_state.cpp
/// Membrane::write_state / read_state (membrane.hpp) in a checkpoint (support/binary_stream.hpp).
#include "mpm/membrane/membrane.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::mpm {

void Membrane::write_state(BinaryWriter& out) const {
  out(x_, v_, f_, stress_, hg_force_, hg_k_, pressure_, ext_work_, damp_loss_, h_prev_, h_n_, h_step_, f_ext_,
      corner_force_, pressure_force_);
}

void Membrane::read_state(BinaryReader& in) {
  const std::size_t nodes = x_.size(), elements = quads_.size();
  in(x_, v_, f_, stress_, hg_force_, hg_k_, pressure_, ext_work_, damp_loss_, h_prev_, h_n_, h_step_, f_ext_,
     corner_force_, pressure_force_);
  if (x_.size() != nodes || v_.size() != nodes || f_.size() != nodes || stress_.size() != elements)
    in.fail("a membrane of another mesh");
}

}  // namespace tetfsi::mpm
