/// @file step_halving.cpp
/// CoupledStepper::step: one step of length h, undone and taken in halves when its solid motion
/// would invert or flatten fluid tets (CoupledSettings::max_step_halvings, coupled_stepper.hpp).
#include <algorithm>
#include <string>

#include "coupling/coupled_stepper.hpp"
#include "mesh/complex_mesher.hpp"  // MeshError
#include "support/number_text.hpp"

namespace tetfsi::coupling {

CoupledStepReport CoupledStepper::step(double h) {
  if (!(h > 0)) throw std::invalid_argument("coupled step: time step must be positive");
  try {
    return step_or_halve(h, settings_.max_step_halvings);
  } catch (const mesh::MeshError& e) {
    if (settings_.max_step_halvings == 0) throw;
    throw mesh::MeshError(std::string(e.what()) + " (also with the step halved " +
                          std::to_string(settings_.max_step_halvings) + " times, to " +
                          number_text(h / (1 << settings_.max_step_halvings)) +
                          " s; simulation.max_step_halvings allows more)");
  }
}

CoupledStepReport CoupledStepper::step_or_halve(double h, int halvings) {
  const auto guarded = [&](CoupledStepReport report) {
    energy_guard_energy_ = report.total_energy();
    return report;
  };
  if (halvings == 0) return guarded(step_once(h, false));
  Snapshot before = snapshot();
  try {
    // The time-splitting baseline is unstable at any step when the added mass exceeds the solid's
    // (Causin, Gerbeau & Nobile 2005): halving cannot help it, and its runs show it.
    return guarded(step_once(h, settings_.scheme == CouplingScheme::kSimultaneous));
  } catch (const mesh::MeshError&) {
    // The solid motion of this step would invert or flatten a tet even with the fluid following:
    // undo the step and take it in two halves, so the mesh can be remeshed in between.
    restore(std::move(before));
  } catch (const EnergyGainError&) {
    restore(std::move(before));  // energy from nowhere (set_energy_guard)
  }
  CoupledStepReport first = step_or_halve(0.5 * h, halvings - 1);
  CoupledStepReport second = step_or_halve(0.5 * h, halvings - 1);
  // The second half's state with the time of both halves.
  second.substeps += first.substeps;
  second.obstacle_clearance = std::min(first.obstacle_clearance, second.obstacle_clearance);
  second.min_substep = std::min(first.min_substep, second.min_substep);
  second.mesh_update.remeshed = second.mesh_update.remeshed || first.mesh_update.remeshed;
  second.mesh_update.seconds += first.mesh_update.seconds;
  second.mesh_update.motion_seconds += first.mesh_update.motion_seconds;
  second.mesh_update.check_seconds += first.mesh_update.check_seconds;
  second.fluid.advect_seconds += first.fluid.advect_seconds;
  second.fluid.forces_seconds += first.fluid.forces_seconds;
  second.fluid.surface_seconds += first.fluid.surface_seconds;
  second.fluid.particle_seconds += first.fluid.particle_seconds;
  second.fluid.assemble_seconds += first.fluid.assemble_seconds;
  second.solid_assemble_seconds += first.solid_assemble_seconds;
  second.interface_seconds += first.interface_seconds;
  second.solve.setup_seconds += first.solve.setup_seconds;
  second.solve.solve_seconds += first.solve.solve_seconds;
  second.solve.iterations += first.solve.iterations;
  second.solve.contact_rounds += first.solve.contact_rounds;
  for (std::size_t k = 0; k < second.compared.size() && k < first.compared.size(); ++k) {
    second.compared[k].seconds += first.compared[k].seconds;
    second.compared[k].iterations += first.compared[k].iterations;
  }
  return second;
}

CoupledStepper::Snapshot CoupledStepper::snapshot() const {
  Snapshot s{fluid_.undo_point(mesh_), {}, previous_vertex_pressure_, {}, {}, time_, step_};
  if (surface_contact_) {
    s.surface_contact_nodes = surface_contact_->touching_nodes();
    s.surface_contact_forces = surface_contact_->touching_forces();
  }
  for (const Solid& solid : solids_) s.solids.push_back(solid.integrator->save_state());
  return s;
}

void CoupledStepper::restore(Snapshot s) {
  fluid_.undo(std::move(s.fluid));
  for (std::size_t i = 0; i < solids_.size(); ++i) solids_[i].integrator->restore_state(s.solids[i]);
  previous_vertex_pressure_ = std::move(s.previous_vertex_pressure);
  if (surface_contact_)
    surface_contact_->set_touching_nodes(std::move(s.surface_contact_nodes), std::move(s.surface_contact_forces));
  time_ = s.time;
  step_ = s.step;
}

}  // namespace tetfsi::coupling
