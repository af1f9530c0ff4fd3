/// @file coupled_stepper_state.cpp
/// CoupledStepper::write_state / read_state and MeshUpdater's (coupled_stepper.hpp): the coupled
/// model's changing state in a checkpoint (support/binary_stream.hpp).
#include "coupling/coupled_stepper.hpp"
#include "mesh/tet_mesh_state.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::coupling {

void MeshUpdater::write_state(BinaryWriter& out) const {
  out(bool(motion_));
  if (!motion_) return;
  out(motion_->reference_positions());
  motion_->write_state(out);
}

void MeshUpdater::read_state(BinaryReader& in, const mesh::TetMesh& mesh) {
  bool cached = false;
  in(cached);
  motion_.reset();
  if (!cached) return;
  mesh::TetMesh reference = mesh;
  in(reference.vertices);
  if (reference.num_vertices() != mesh.num_vertices()) in.fail("a mesh motion of another mesh");
  motion_ = make_motion(reference);
  motion_->read_state(in);
}

void CoupledStepper::write_state(BinaryWriter& out) const {
  out(mesh_, std::uint64_t(solids_.size()));
  for (const Solid& s : solids_) {
    mesh::serialize_maps(out, const_cast<mesh::Submesh&>(s.submesh));
    s.integrator->write_state(out);
  }
  fluid_.write_state(out);
  solver_->write_state(out);
  mesh_updater_->write_state(out);
  out(previous_vertex_pressure_, min_dihedral_deg_, pressure_force_, fluid_mesh_moved_vertices_, time_, step_,
      bool(surface_contact_));
  if (surface_contact_) out(surface_contact_->touching_nodes(), surface_contact_->touching_forces());
  std::vector<int> keys;
  std::vector<double> volumes;
  for (const auto& [key, volume] : closed_volumes_.reference_volumes()) keys.push_back(key), volumes.push_back(volume);
  out(keys, volumes);
}

void CoupledStepper::read_state(BinaryReader& in) {
  in(mesh_);
  in.expect_size(solids_.size(), "solids");
  for (Solid& s : solids_) {
    mesh::serialize_maps(in, s.submesh);
    if (s.submesh.to_parent_vertex.size() != static_cast<std::size_t>(s.model->num_nodes()))
      in.fail("a solid of another mesh");
    for (int v : s.submesh.to_parent_vertex)
      if (v < 0 || v >= mesh_.num_vertices()) in.fail("a solid node outside the mesh");
    s.integrator->read_state(in);
  }
  fluid_.read_state(in);
  solver_->read_state(in);
  mesh_updater_->read_state(in, mesh_);
  bool contact = false;
  in(previous_vertex_pressure_, min_dihedral_deg_, pressure_force_, fluid_mesh_moved_vertices_, time_, step_, contact);
  if (contact != bool(surface_contact_)) in.fail("a coupled state with another surface-contact setting");
  if (surface_contact_) {
    std::vector<int> touching;
    std::vector<double> forces;
    in(touching, forces);
    surface_contact_->set_touching_nodes(std::move(touching), std::move(forces));
  }
  if (previous_vertex_pressure_.size() != static_cast<std::size_t>(mesh_.num_vertices()))
    in.fail("a previous pressure of another mesh");
  std::vector<int> keys;
  std::vector<double> volumes;
  in(keys, volumes);
  if (keys.size() != volumes.size()) in.fail("closed-region volumes without their keys");
  std::map<int, double> reference;
  for (std::size_t k = 0; k < keys.size(); ++k) reference[keys[k]] = volumes[k];
  closed_volumes_.set_reference_volumes(std::move(reference));
}

}  // namespace tetfsi::coupling
