/// @file fluid_solver_state.cpp
/// FluidSolver::write_state / read_state: the solver's changing state as a binary block of a
/// checkpoint (support/binary_stream.hpp), bit for bit.
#include "fluid/fluid_solver.hpp"
#include "support/binary_stream.hpp"

#include <memory>
#include <utility>

namespace tetfsi::fluid {

template <class A>
void serialize(A& a, BoundaryFace& f) {
  a(f.tet, f.local_face, f.nodes, f.normal, f.area, f.other_subdomain);
}

template <class A>
void serialize(A& a, FluidMesh& m) {
  a(m.nodes, m.node_to_mesh_vertex, m.mesh_vertex_to_node, m.tets, m.tet_to_mesh_tet, m.volume, m.grad.stored,
    m.neighbor, m.boundary_faces, m.dual_volume, m.node_tets);
}

// The solver's mesh (shared with its copies): written as the mesh, read into a mesh of its own.
void serialize(BinaryWriter& a, std::shared_ptr<FluidMesh>& m) { a(*m); }
void serialize(BinaryReader& a, std::shared_ptr<FluidMesh>& m) {
  auto read = std::make_shared<FluidMesh>();
  a(*read);
  m = std::move(read);
}

template <class A>
void serialize(A& a, ClassifiedBoundary& b) {
  a(b.face_kind, b.face_patch, b.node_kind, b.flux_faces, b.flux_velocity, b.flux, b.closed, b.flux_imbalance);
}

template <class A>
void serialize(A& a, LiquidGeometry& g) {
  a(g.liquid_volume, g.wet_moment, g.first_moment, g.is_liquid, g.num_air_nodes);
}

// The fields (shared with the solver's copies until written): written as the fields, read into
// fields of their own.
template <class A>
void serialize(A& a, FluidFields& f) {
  a(f.velocity, f.smoke, f.temperature);
}
void serialize(BinaryWriter& a, std::shared_ptr<FluidFields>& f) { a(*f); }
void serialize(BinaryReader& a, std::shared_ptr<FluidFields>& f) {
  auto read = std::make_shared<FluidFields>();
  a(*read);
  f = std::move(read);
}

// The tets and labels the mesh was built from (shared with the solver's copies), as the mesh.
void serialize(BinaryWriter& a, std::shared_ptr<const FluidSolver::SourceTopology>& s) { a(s->tets, s->subdomain); }
void serialize(BinaryReader& a, std::shared_ptr<const FluidSolver::SourceTopology>& s) {
  auto read = std::make_shared<FluidSolver::SourceTopology>();
  a(read->tets, read->subdomain);
  s = std::move(read);
}

template <class A>
void serialize(A& a, ParticleSet& s) {
  a(s.x, s.v, s.grad_v, s.tet, s.seed_count);
}

// The particles (shared with the solver's copies; none before the first step): a flag, then the set.
void serialize(BinaryWriter& a, std::shared_ptr<ParticleSet>& s) {
  a(static_cast<bool>(s));
  if (s) a(*s);
}
void serialize(BinaryReader& a, std::shared_ptr<ParticleSet>& s) {
  bool present = false;
  a(present);
  s.reset();
  if (!present) return;
  auto read = std::make_shared<ParticleSet>();
  a(*read);
  const std::size_t n = read->x.size();
  if (read->v.size() != n || read->tet.size() != n || (!read->grad_v.empty() && read->grad_v.size() != n))
    a.fail("particle arrays of different sizes");
  s = std::move(read);
}

template <class Archive>
void FluidSolver::state(Archive& a) {
  a(mesh_, source_, fields_, advected_divergence_,
    pressure_, boundary_, initialized_, free_surface_, level_set_, liquid_, target_volume_, particles_);
}

void FluidSolver::write_state(BinaryWriter& out) const { const_cast<FluidSolver*>(this)->state(out); }

void FluidSolver::read_state(BinaryReader& in) {
  const bool liquid = free_surface_;
  state(in);
  spare_ = SpareMesh();    // of the mesh before the read
  viscous_rings_.clear();  // of the mesh before the read; remade from the restored one
  if (free_surface_ != liquid) in.fail("a fluid state with another kind of fluid (smoke or liquid)");
  if (particles_) {
    const bool apic = params_.particles.transfer == ParticleTransfer::kApic;
    if (!params_.particles.enabled() || (apic ? particles_->grad_v.size() != particles_->x.size() : !particles_->grad_v.empty()))
      in.fail("particles of another transfer (fluid.advection)");
    for (int t : particles_->tet)
      if (t < 0 || t >= mesh_->num_tets()) in.fail("a particle in a tet the mesh does not have");
  }
  transferred_velocity_.clear();
  particles_on_mesh_ = false;
}

}  // namespace tetfsi::fluid
