/// @file fluid_solver_particles.cpp
/// FluidSolver's particle steps (FluidParams::particles; particles/particles.hpp): the first
/// seeding, the motion to the new mesh with P2G (predict), and G2P after the pressure (finish,
/// apply_pressure).
#include <memory>
#include <stdexcept>
#include <utility>

#include "fluid/fluid_solver.hpp"
#include "fluid/liquid/velocity_extension.hpp"
#include "fluid/particles/particle_motion.hpp"
#include "fluid/particles/seeding.hpp"
#include "fluid/particles/surface_layer.hpp"
#include "fluid/particles/transfer.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::fluid {

void FluidSolver::seed_particles() {
  if (particles_) return;
  particles_ = std::make_shared<ParticleSet>();
  const std::vector<char> kept = kept_tets();
  add_particles(*mesh_, free_surface_ ? liquid_.liquid_volume : mesh_->volume,
                free_surface_ ? level_set_ : Eigen::VectorXd(), params_.particles.per_tet, fields_->velocity, &kept,
                params_.particles.transfer == ParticleTransfer::kApic, *particles_);
}

std::shared_ptr<ParticleSet> FluidSolver::advected_particles(const std::vector<double>* weight,
                                                             const PointLocator& old_locator, double h) {
  seed_particles();
  // The set an undo point (a copy of the solver) shares is copied, never moved.
  std::shared_ptr<ParticleSet> moved =
      particles_.use_count() == 1 ? std::move(particles_) : std::make_shared<ParticleSet>(*particles_);
  particles_.reset();
  advect_particles(*mesh_, fields_->velocity, weight, old_locator, h, *moved);
  return moved;
}

void FluidSolver::transfer_to_mesh(std::shared_ptr<ParticleSet> moved, const std::vector<int>& old_to_new,
                                   StepReport& rep) {
  const Stopwatch clock;
  ParticleSet& particles = *moved;
  const PointLocator locator(*mesh_);
  locate_particles(*mesh_, locator, old_to_new, particles);
  if (free_surface_) rep.particles_removed += keep_in_liquid(*mesh_, locator, level_set_, particles).second;
  const std::vector<double>& fluid_volume = free_surface_ ? liquid_.liquid_volume : mesh_->volume;
  rep.particles_removed += delete_crowded_particles(*mesh_, fluid_volume, params_.particles.per_tet, particles);
  TetVectors& v = writable_fields().velocity;
  const std::vector<char> known =
      particles_to_tets(*mesh_, particles, particle_masses(particles, fluid_volume, params_.density), v);
  if (free_surface_) {
    // A liquid tet without particles (at the surface) takes the extension of its neighbours'
    // velocities (velocity_extension.hpp), as the air does after the projection: the mesh
    // advection's value there reads the air's extended velocity and is off by a few per cent even
    // in a uniform flow (a ball in free flight, tests/fluid/test_particle_flows.cpp).
    extend_velocity(*mesh_, known, liquid_options_.extension_layers, v);
    smooth_surface_layer(*mesh_, liquid_.liquid_volume, v);
  }
  // New particles take the velocity the others just gave the mesh.
  const std::vector<char> kept = kept_tets();
  rep.particles_added = add_particles(*mesh_, fluid_volume, free_surface_ ? level_set_ : Eigen::VectorXd(),
                                      params_.particles.per_tet, v, &kept,
                                      params_.particles.transfer == ParticleTransfer::kApic, particles);
  if (params_.particles.transfer == ParticleTransfer::kFlip) transferred_velocity_ = v;
  particles_ = std::move(moved);
  particles_on_mesh_ = true;
  rep.num_particles = particles_->size();
  rep.particle_seconds += clock.seconds();
}

void FluidSolver::transfer_to_particles(StepReport& rep) {
  if (!particles_on_mesh_) return;
  const Stopwatch clock;
  if (particles_.use_count() > 1) particles_ = std::make_shared<ParticleSet>(*particles_);
  const std::vector<char> kept = kept_tets();
  tets_to_particles(*mesh_, fields_->velocity, transferred_velocity_, params_.particles.flip_ratio, &kept, *particles_);
  for (const Eigen::Vector3d& v : particles_->v)
    if (!v.allFinite()) throw std::runtime_error("FluidSolver: a particle velocity became NaN/Inf (diverged)");
  transferred_velocity_ = TetVectors();
  particles_on_mesh_ = false;
  rep.num_particles = particles_->size();
  rep.particle_seconds += clock.seconds();
}

}  // namespace tetfsi::fluid
