/// @file newmark_state.cpp
/// NewmarkIntegrator::write_state / read_state: the integrator's changing state as a binary block
/// of a checkpoint (support/binary_stream.hpp).
#include "solid/contact/surface_contact.hpp"
#include "solid/integrator/newmark.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::solid {

template <class A>
void serialize(A& a, StepStats& s) {
  a(s.step, s.time, s.assembly_seconds, s.solve_seconds, s.solver_iterations, s.kinetic, s.strain,
    s.gravity_potential, s.spring, s.inverted, s.contacts);
}

void NewmarkIntegrator::write_state(BinaryWriter& out) const {
  out(d_, u_, time_, step_, stats_, last_contact_nodes_, last_contact_forces_, prescribed_, f_ext_, bool(self_contact_));
  if (self_contact_) out(self_contact_->touching_nodes(), self_contact_->touching_forces());
}

void NewmarkIntegrator::read_state(BinaryReader& in) {
  const auto n = d_.size();
  bool self = false;
  in(d_, u_, time_, step_, stats_, last_contact_nodes_, last_contact_forces_, prescribed_, f_ext_, self);
  if (d_.size() != n || u_.size() != n || prescribed_.size() != n || f_ext_.size() != n)
    in.fail("a solid state of another mesh");
  if (self != bool(self_contact_)) in.fail("a solid state with another self-contact setting");
  if (self_contact_) {
    std::vector<int> touching;
    std::vector<double> forces;
    in(touching, forces);
    self_contact_->set_touching_nodes(std::move(touching), std::move(forces));
  }
  active_.clear();
}

}  // namespace tetfsi::solid
