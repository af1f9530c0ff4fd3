#include "fluid/fluid_solver.hpp"

#include "fluid/advection/point_locator.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid/liquid/velocity_extension.hpp"
#include "fluid/viscosity/node_fit.hpp"

#include <algorithm>
#include <memory>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace tetfsi::fluid {
namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

FluidSolver::FluidSolver(FluidParams params) : params_(std::move(params)) {
  if (!(params_.density > 0.0)) throw std::invalid_argument("FluidSolver: density must be positive");
}

bool FluidSolver::built_from(const mesh::TetMesh& mesh) const {
  return initialized_ && mesh.tets == source_->tets && mesh.subdomain == source_->subdomain &&
         mesh.num_vertices() == static_cast<int>(mesh_->mesh_vertex_to_node.size());
}

FluidFields& FluidSolver::writable_fields() {
  if (fields_.use_count() > 1) fields_ = std::make_shared<FluidFields>(*fields_);  // an undo point's
  return *fields_;
}

bool FluidSolver::moves_in_place(const mesh::TetMesh& mesh) const {
  return built_from(mesh) && !free_surface_ && params_.advection != AdvectionScheme::kBfecc &&
         !params_.particles.enabled();
}

FluidSolver::UndoPoint FluidSolver::undo_point(const mesh::TetMesh& mesh) const {
  UndoPoint point{*this, {}};
  if (moves_in_place(mesh)) {
    point.nodes = mesh_->nodes;
    point.solver.mesh_.reset();
  }
  return point;
}

void FluidSolver::undo(UndoPoint point) {
  if (point.solver.mesh_) {
    *this = std::move(point.solver);
    return;
  }
  // The mesh the point was taken on, moved since (in place or into new storage, with the same
  // topology either way): its geometry goes back to the point's node positions.
  std::shared_ptr<FluidMesh> moved = std::move(mesh_);
  *this = std::move(point.solver);
  update_fluid_mesh_geometry(std::move(point.nodes), *moved);
  mesh_ = std::move(moved);
}

void FluidSolver::set_mesh(const mesh::TetMesh& mesh, std::shared_ptr<FluidMesh> fluid_mesh, bool same_topology) {
  spare_.mesh = std::exchange(mesh_, std::move(fluid_mesh));
  spare_.same_topology = same_topology;
  if (same_topology) return;
  viscous_rings_.clear();
  source_ = std::make_shared<const SourceTopology>(SourceTopology{mesh.tets, mesh.subdomain});
}

std::shared_ptr<FluidMesh> FluidSolver::moved_mesh_storage() {
  std::shared_ptr<FluidMesh> storage = std::move(spare_.mesh);
  const bool has_topology = storage && spare_.same_topology;
  spare_ = SpareMesh();
  if (!storage || storage.use_count() > 1) storage = std::make_shared<FluidMesh>();
  else if (has_topology) return storage;
  *storage = *mesh_;  // copy-assigned: a spare's arrays keep their capacity
  return storage;
}

void FluidSolver::initialize(const mesh::TetMesh& mesh, FluidFields fields) {
  initialized_ = false;
  set_mesh(mesh, std::make_shared<FluidMesh>(build_fluid_mesh(mesh)), false);
  const int n = mesh_->num_tets();
  if (fields.velocity.empty()) fields.velocity.assign(n, Eigen::Vector3d::Zero());
  if (fields.smoke.size() == 0) fields.smoke = Eigen::VectorXd::Zero(n);
  if (fields.temperature.size() == 0)
    fields.temperature = Eigen::VectorXd::Constant(n, params_.buoyancy.ambient_temperature);
  if (static_cast<int>(fields.velocity.size()) != n || fields.smoke.size() != n || fields.temperature.size() != n)
    throw std::invalid_argument("FluidSolver::initialize: fields must have one value per fluid tet (" +
                                std::to_string(n) + ")");
  fields_ = std::make_shared<FluidFields>(std::move(fields));
  pressure_ = Eigen::VectorXd::Zero(mesh_->num_nodes());
  initialized_ = true;
}

void FluidSolver::set_liquid(Eigen::VectorXd level_set, LiquidOptions options) {
  if (!initialized_) throw std::logic_error("FluidSolver::set_liquid: initialize() first");
  if (level_set.size() != mesh_->num_nodes())
    throw std::invalid_argument("FluidSolver::set_liquid: one level set value per fluid node expected");
  if (!(options.band > 0.0)) throw std::invalid_argument("FluidSolver::set_liquid: the band must be positive");
  if (options.extension_layers < 0) throw std::invalid_argument("FluidSolver::set_liquid: extension_layers < 0");
  liquid_options_ = options;
  snap_to_surface(*mesh_, level_set);
  wet_enclosed_zeros(*mesh_, level_set);
  // The sampled distance is made the distance to its zero set once; the steps then keep the cut
  // tets' values, which hold the surface, and redistance the other nodes only.
  redistance(*mesh_, level_set, options.band);
  level_set_ = std::move(level_set);
  liquid_ = liquid_geometry(*mesh_, level_set_);
  target_volume_ = liquid_.total_volume();
  if (!(target_volume_ > 0.0)) throw std::invalid_argument("FluidSolver::set_liquid: the level set holds no liquid");
  free_surface_ = true;
  extend_liquid_velocity();
}

std::vector<char> FluidSolver::kept_tets() const {
  std::vector<char> keep(mesh_->num_tets(), 1);
  if (free_surface_)
    for (int t = 0; t < mesh_->num_tets(); ++t)
      keep[t] = liquid_.liquid_volume[t] > 0.0 &&
                liquid_.liquid_volume[t] >= liquid_options_.min_kept_fraction * mesh_->volume[t];
  return keep;
}

void FluidSolver::extend_liquid_velocity() {
  extend_velocity(*mesh_, kept_tets(), liquid_options_.extension_layers, writable_fields().velocity);
}

void FluidSolver::update_liquid(Eigen::VectorXd phi, StepReport& rep) {
  snap_to_surface(*mesh_, phi);
  wet_enclosed_zeros(*mesh_, phi);
  redistance(*mesh_, phi, liquid_options_.band, true);
  const double tracked = liquid_volume(*mesh_, phi);
  rep.volume_drift = (tracked - target_volume_) / target_volume_;
  if (liquid_options_.restore_volume) restore_volume(*mesh_, phi, target_volume_);
  level_set_ = std::move(phi);
  liquid_ = liquid_geometry(*mesh_, level_set_);
  rep.liquid_volume = liquid_.total_volume();
}

void FluidSolver::apply_sources(const BoundaryConditions& bc, double h) {
  // A liquid's sources fill their box with liquid (phi = min(phi, distance to the box)); what
  // they add is added to the volume the run keeps. An inflow patch pours liquid: its region swept
  // one mean edge length into the fluid along the inflow velocity is kept full of liquid moving at
  // that velocity, so the patch's faces have liquid nodes and its flux enters the cut-tet system.
  struct Pouring {
    Region layer;                 ///< the patch region swept one edge along its velocity
    const BoundaryPatch* patch;
  };
  std::vector<Pouring> pouring;
  if (free_surface_)
    for (const BoundaryPatch& p : bc.patches)
      if (p.kind == FaceKind::kInflow && p.velocity.norm() > 0) {
        const Eigen::Vector3d reach = mesh_->mean_edge_length() * p.velocity.normalized();
        pouring.push_back({{p.region.lo.cwiseMin(p.region.lo + reach), p.region.hi.cwiseMax(p.region.hi + reach)}, &p});
      }
  if (free_surface_ && (!bc.sources.empty() || !pouring.empty())) {
    const double before = liquid_.total_volume();
    auto fill = [&](const Region& r) {
      for (int i = 0; i < mesh_->num_nodes(); ++i)
        level_set_[i] = std::min(level_set_[i], box_distance(mesh_->nodes[i], r.lo, r.hi));
    };
    for (const SourceVolume& s : bc.sources) fill(s.region);
    for (const Pouring& p : pouring) fill(p.layer);
    liquid_ = liquid_geometry(*mesh_, level_set_);
    target_volume_ += liquid_.total_volume() - before;
  }
  for (const Pouring& p : pouring)
    for (int t = 0; t < mesh_->num_tets(); ++t)
      if (p.layer.contains(mesh_->centroid(t)))
        writable_fields().velocity[t] = p.patch->velocity_field ? p.patch->velocity_field(mesh_->centroid(t)) : p.patch->velocity;
  // The liquid the inflow faces let in over the step, h sum_f A_f (-u_f.n_f) over the faces with
  // liquid at every node, joins the volume the run keeps: the layer stays full (its back-traces end
  // on the wall), so the refill above does not see it.
  if (!pouring.empty()) {
    double inflow = 0;
    for (size_t f = 0; f < mesh_->boundary_faces.size(); ++f) {
      if (boundary_.face_kind[f] != FaceKind::kInflow) continue;
      const BoundaryFace& bf = mesh_->boundary_faces[f];
      if (!(level_set_[bf.nodes[0]] < 0 && level_set_[bf.nodes[1]] < 0 && level_set_[bf.nodes[2]] < 0)) continue;
      const BoundaryPatch& p = bc.patches[boundary_.face_patch[f]];
      Eigen::Vector3d u = p.velocity;
      if (p.velocity_field)
        u = (p.velocity_field(mesh_->nodes[bf.nodes[0]]) + p.velocity_field(mesh_->nodes[bf.nodes[1]]) +
             p.velocity_field(mesh_->nodes[bf.nodes[2]])) / 3.0;
      inflow -= bf.area * u.dot(bf.normal);
    }
    target_volume_ += h * inflow;
  }
  for (const SourceVolume& s : bc.sources)
    for (int t = 0; t < mesh_->num_tets(); ++t)
      if (s.region.contains(mesh_->centroid(t))) {
        writable_fields().smoke[t] = s.smoke;
        writable_fields().temperature[t] = s.temperature;
        if (s.set_velocity) writable_fields().velocity[t] = s.velocity;
      }
  for (size_t f = 0; f < mesh_->boundary_faces.size(); ++f)
    if (boundary_.face_kind[f] == FaceKind::kInflow) {
      const BoundaryPatch& p = bc.patches[boundary_.face_patch[f]];
      const int t = mesh_->boundary_faces[f].tet;
      writable_fields().smoke[t] = p.smoke;
      writable_fields().temperature[t] = p.temperature;
    }
}

StepReport FluidSolver::step(const mesh::TetMesh& mesh, const BoundaryConditions& bc, double h) {
  if (!viscous()) return finish(bc, h, predict(mesh, bc, h));
  struct After {  // predict() without the viscous step, also when it throws
    bool& flag;
    explicit After(bool& f) : flag(f) { flag = true; }
    ~After() { flag = false; }
  };
  StepReport rep;
  {
    After after(viscosity_after_projection_);
    rep = predict(mesh, bc, h);
  }
  const ProjectionReport first = project_velocity(h);
  apply_viscosity_step(bc, h, rep);
  rep = finish(bc, h, rep);
  pressure_ += first.pressure;
  rep.solve_seconds += first.solve_seconds;
  rep.iterations += first.solve.iterations;
  rep.assemble_seconds += first.assemble_seconds;
  return rep;
}

StepReport FluidSolver::predict(const mesh::TetMesh& mesh, const BoundaryConditions& bc, double h) {
  if (!initialized_) throw std::logic_error("FluidSolver::step: initialize() first");
  if (!(h > 0.0)) throw std::invalid_argument("FluidSolver::step: h must be positive");
  StepReport rep;
  double t0 = now();
  if (moves_in_place(mesh) && mesh_.use_count() == 1) {
    // The mesh only moved and nothing else holds it: advect onto the moved tets' centroids, then
    // move the mesh itself (one fluid mesh in memory, not the old and the new one).
    spare_ = SpareMesh();
    AdvectionReport adv;
    const BoundaryExits exits = boundary_exits(*mesh_, bc);
    // The moved nodes gathered once (in node order: the centroids then read neighbouring nodes).
    std::vector<Eigen::Vector3d> nodes = moved_nodes(mesh, *mesh_);
    fields_ = std::make_shared<FluidFields>(advect_onto_moved(*mesh_, *fields_, nodes, h, &adv, params_.advection, &exits));
    rep.clamped_traces = adv.clamped + adv.outside_start;
    rep.advect_seconds = now() - t0;
    t0 = now();
    update_fluid_mesh_geometry(std::move(nodes), *mesh_);
    rep.assemble_seconds += now() - t0;
    if (keep_advected_divergence_) advected_divergence_ = gradient_transpose_volume(*mesh_, fields_->velocity);
    return add_forces(bc, h, rep);
  }
  // A moved (not remeshed) mesh keeps its topology: only its geometry is recomputed.
  const bool same_topology = built_from(mesh);
  std::shared_ptr<FluidMesh> new_mesh_storage =
      same_topology ? moved_mesh_storage() : std::make_shared<FluidMesh>(build_fluid_mesh(mesh));
  FluidMesh& new_mesh = *new_mesh_storage;
  if (same_topology) update_fluid_mesh_geometry(mesh, new_mesh);
  rep.assemble_seconds += now() - t0;
  t0 = now();
  Eigen::VectorXd phi;
  std::vector<double> weight;  // a liquid's node averages: by liquid volume (semi_lagrangian.hpp)
  if (free_surface_) {
    weight.resize(mesh_->num_tets());
    for (int t = 0; t < mesh_->num_tets(); ++t)
      weight[t] = std::max(liquid_.liquid_volume[t], liquid_options_.air_weight * mesh_->volume[t]);
  }
  // One point locator of the old mesh serves the level set's, the particles' and the fields' traces.
  std::optional<PointLocator> old_locator;
  if (free_surface_ || params_.particles.enabled()) old_locator.emplace(*mesh_);
  if (free_surface_)
    phi = (liquid_options_.bfecc ? advect_nodal_bfecc : advect_nodal)(*mesh_, fields_->velocity, level_set_, new_mesh,
                                                                      h, nullptr, &weight, &*old_locator);
  rep.surface_seconds = now() - t0;
  std::shared_ptr<ParticleSet> moved;
  std::vector<int> old_to_new;  // the particles' walks start at their tets' images on a moved mesh
  if (params_.particles.enabled()) {
    t0 = now();
    moved = advected_particles(free_surface_ ? &weight : nullptr, *old_locator, h);
    if (same_topology) old_to_new = matching_tets(*mesh_, new_mesh);
    rep.particle_seconds = now() - t0;
  }
  t0 = now();
  AdvectionReport adv;
  const BoundaryExits exits = boundary_exits(*mesh_, bc);
  fields_ = std::make_shared<FluidFields>(advect(*mesh_, *fields_, new_mesh, h, &adv, params_.advection, &exits, free_surface_ ? &weight : nullptr,
                   old_locator ? &*old_locator : nullptr));
  set_mesh(mesh, std::move(new_mesh_storage), same_topology);
  rep.clamped_traces = adv.clamped + adv.outside_start;
  rep.advect_seconds = now() - t0;
  if (free_surface_) {
    t0 = now();
    update_liquid(std::move(phi), rep);
    rep.surface_seconds += now() - t0;
  }
  if (moved) transfer_to_mesh(std::move(moved), old_to_new, rep);
  if (keep_advected_divergence_) advected_divergence_ = gradient_transpose_volume(*mesh_, fields_->velocity);

  return add_forces(bc, h, rep);
}

StepReport FluidSolver::add_forces(const BoundaryConditions& bc, double h, StepReport rep) {
  double t0 = now();
  boundary_ = classify_boundary(*mesh_, bc);
  rep.assemble_seconds += now() - t0;
  t0 = now();
  apply_sources(bc, h);
  rep.forces_seconds = now() - t0;
  // Viscosity acts on the advected (divergence-free up to the advection's error) field, before the
  // body forces: a force that the pressure balances (still water) never meets the no-slip walls.
  if (viscous() && !viscosity_after_projection_) apply_viscosity_step(bc, h, rep);
  t0 = now();
  if (params_.apply_gravity)
    for (auto& u : writable_fields().velocity) u += h * params_.gravity;
  add_buoyancy(*mesh_, writable_fields().smoke, writable_fields().temperature, params_.gravity, params_.buoyancy, h, writable_fields().velocity);
  add_vorticity_confinement(*mesh_, params_.vorticity_epsilon, h, writable_fields().velocity);
  rep.forces_seconds += now() - t0;
  return rep;
}

bool FluidSolver::viscous() const {
  if (params_.viscosity > 0) return true;
  for (const auto& r : params_.viscosity_regions)
    if (r.second > 0) return true;
  return false;
}

void FluidSolver::apply_viscosity_step(const BoundaryConditions& bc, double h, StepReport& rep) {
  const double t0 = now();
  std::vector<double> mu(mesh_->num_tets(), params_.viscosity);
  if (!params_.viscosity_regions.empty())
    for (int t = 0; t < mesh_->num_tets(); ++t)
      for (const auto& [region, value] : params_.viscosity_regions)
        if (region.contains(mesh_->centroid(t))) {
          mu[t] = value;
          break;
        }
  // The fluid in each tet: all of it, or a liquid's part (the air is void and carries no stress).
  const std::vector<double>& weight = free_surface_ ? liquid_.liquid_volume : mesh_->volume;
  const ViscousNodes nodes = viscous_nodes(*mesh_, boundary_, bc, params_.walls);
  if (viscous_rings_.empty()) viscous_rings_ = node_rings(*mesh_);
  ViscosityReport vr = apply_viscosity(*mesh_, mu, weight, params_.density, nodes, h, params_.viscous_solver,
                                       writable_fields().velocity, &viscous_rings_);
  viscous_force_.assign(mesh_->num_nodes(), Eigen::Vector3d::Zero());
  viscous_stiffness_.assign(mesh_->num_nodes(), Eigen::Matrix3d::Zero());
  for (const BoundaryFace& bf : mesh_->boundary_faces)
    if (bf.other_subdomain >= mesh::solid_subdomain(0))
      for (int i : bf.nodes) {
        viscous_force_[i] = vr.wall_force[i];
        viscous_stiffness_[i] = vr.wall_stiffness[i];
      }
  rep.viscous_iterations = vr.iterations;
  rep.viscosity_seconds = now() - t0;
}

Eigen::Vector3d FluidSolver::viscous_force(int subdomain) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  if (viscous_force_.empty()) return f;
  std::vector<char> seen(mesh_->num_nodes(), 0);
  for (const BoundaryFace& bf : mesh_->boundary_faces)
    if (bf.other_subdomain == subdomain)
      for (int i : bf.nodes)
        if (!seen[i]) {
          seen[i] = 1;
          f += viscous_force_[i];
        }
  return f;
}

StepReport FluidSolver::apply_pressure(Eigen::VectorXd pressure, double h, StepReport rep) {
  if (pressure.size() != mesh_->num_nodes())
    throw std::invalid_argument("FluidSolver::apply_pressure: one pressure per fluid node expected");
  pressure_ = std::move(pressure);
  if (free_surface_) {  // u_t -= (h/rho) B_t p on the liquid, then the extension into the air
    apply_wet_pressure(*mesh_, liquid_, pressure_, h, params_.density, writable_fields().velocity);
    const double t0 = now();
    extend_liquid_velocity();
    rep.surface_seconds += now() - t0;
    rep.liquid_volume = liquid_.total_volume();
  } else {
    const TetVectors grad_p = gradient(*mesh_, pressure_);
    const double scale = h / params_.density;
    for (int t = 0; t < mesh_->num_tets(); ++t) writable_fields().velocity[t] -= scale * grad_p[t];
  }
  transfer_to_particles(rep);
  for (const auto& u : fields_->velocity)
    if (!u.allFinite()) throw std::runtime_error("FluidSolver: velocity became NaN/Inf (diverged)");
  if (!pressure_.allFinite()) throw std::runtime_error("FluidSolver: pressure became NaN/Inf (diverged)");
  rep.num_tets = mesh_->num_tets();
  rep.num_nodes = mesh_->num_nodes();
  report_energies(rep);
  return rep;
}

void FluidSolver::report_energies(StepReport& rep) const {
  rep.kinetic_energy = params_.density * (free_surface_ ? liquid_kinetic_energy(liquid_, fields_->velocity)
                                                        : kinetic_energy(*mesh_, fields_->velocity));
  rep.gravity_potential = 0.0;
  if (!params_.apply_gravity) return;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // int x dV over the fluid
  for (int t = 0; t < mesh_->num_tets(); ++t)
    moment += free_surface_ ? liquid_.first_moment[t] : Eigen::Vector3d(mesh_->volume[t] * mesh_->centroid(t));
  rep.gravity_potential = -params_.density * params_.gravity.dot(moment);
}

StepReport FluidSolver::project_only(const BoundaryConditions& bc, double h) {
  if (!initialized_) throw std::logic_error("FluidSolver::project_only: initialize() first");
  const double t0 = now();
  boundary_ = classify_boundary(*mesh_, bc);
  StepReport rep;
  rep.assemble_seconds = now() - t0;
  return finish(bc, h, rep);
}

ProjectionReport FluidSolver::project_velocity(double h) {
  // A liquid that fills every node has no free surface this step: the ordinary projection.
  const bool surface = free_surface_ && liquid_.num_air_nodes > 0;
  return surface ? project_free_surface(*mesh_, boundary_, liquid_, h, params_.density, writable_fields().velocity, params_.solver)
                 : project(*mesh_, boundary_, h, params_.density, writable_fields().velocity, params_.solver);
}

StepReport FluidSolver::finish(const BoundaryConditions&, double h, StepReport rep) {
  ProjectionReport pr = project_velocity(h);
  pressure_ = std::move(pr.pressure);
  if (free_surface_) {
    const double t0 = now();
    extend_liquid_velocity();
    rep.surface_seconds += now() - t0;
    rep.liquid_volume = liquid_.total_volume();
  }
  transfer_to_particles(rep);
  for (const auto& u : fields_->velocity)
    if (!u.allFinite()) throw std::runtime_error("FluidSolver: velocity became NaN/Inf (diverged)");
  if (!pressure_.allFinite()) throw std::runtime_error("FluidSolver: pressure became NaN/Inf (diverged)");
  rep.num_tets = mesh_->num_tets();
  rep.num_nodes = mesh_->num_nodes();
  rep.unknowns = pr.unknowns;
  rep.assemble_seconds += pr.assemble_seconds;
  rep.solve_seconds = pr.solve_seconds;
  rep.iterations = pr.solve.iterations;
  rep.residual = pr.solve.relative_residual;
  rep.max_divergence = pr.max_divergence;
  report_energies(rep);
  return rep;
}

Eigen::Vector3d FluidSolver::pressure_force(int subdomain) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const BoundaryFace& bf : mesh_->boundary_faces)
    if (bf.other_subdomain == subdomain)
      f += bf.area * (pressure_[bf.nodes[0]] + pressure_[bf.nodes[1]] + pressure_[bf.nodes[2]]) / 3.0 * bf.normal;
  return f;
}

}  // namespace tetfsi::fluid
