#include "fluid/fluid_solver.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

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
  return initialized_ && mesh.tets == source_tets_ && mesh.subdomain == source_subdomain_ &&
         mesh.num_vertices() == static_cast<int>(mesh_.mesh_vertex_to_node.size());
}

void FluidSolver::set_mesh(const mesh::TetMesh& mesh, FluidMesh fluid_mesh, bool same_topology) {
  mesh_ = std::move(fluid_mesh);
  if (same_topology) return;
  source_tets_ = mesh.tets;
  source_subdomain_ = mesh.subdomain;
}

void FluidSolver::initialize(const mesh::TetMesh& mesh, FluidFields fields) {
  initialized_ = false;
  set_mesh(mesh, build_fluid_mesh(mesh), false);
  const int n = mesh_.num_tets();
  if (fields.velocity.empty()) fields.velocity.assign(n, Eigen::Vector3d::Zero());
  if (fields.smoke.size() == 0) fields.smoke = Eigen::VectorXd::Zero(n);
  if (fields.temperature.size() == 0)
    fields.temperature = Eigen::VectorXd::Constant(n, params_.buoyancy.ambient_temperature);
  if (static_cast<int>(fields.velocity.size()) != n || fields.smoke.size() != n || fields.temperature.size() != n)
    throw std::invalid_argument("FluidSolver::initialize: fields must have one value per fluid tet (" +
                                std::to_string(n) + ")");
  fields_ = std::move(fields);
  pressure_ = Eigen::VectorXd::Zero(mesh_.num_nodes());
  initialized_ = true;
}

void FluidSolver::apply_sources(const BoundaryConditions& bc) {
  for (const SourceVolume& s : bc.sources)
    for (int t = 0; t < mesh_.num_tets(); ++t)
      if (s.region.contains(mesh_.centroid(t))) {
        fields_.smoke[t] = s.smoke;
        fields_.temperature[t] = s.temperature;
        if (s.set_velocity) fields_.velocity[t] = s.velocity;
      }
  for (size_t f = 0; f < mesh_.boundary_faces.size(); ++f)
    if (boundary_.face_kind[f] == FaceKind::kInflow) {
      const BoundaryPatch& p = bc.patches[boundary_.face_patch[f]];
      const int t = mesh_.boundary_faces[f].tet;
      fields_.smoke[t] = p.smoke;
      fields_.temperature[t] = p.temperature;
    }
}

StepReport FluidSolver::step(const mesh::TetMesh& mesh, const BoundaryConditions& bc, double dt) {
  return finish(bc, dt, predict(mesh, bc, dt));
}

StepReport FluidSolver::predict(const mesh::TetMesh& mesh, const BoundaryConditions& bc, double dt) {
  if (!initialized_) throw std::logic_error("FluidSolver::step: initialize() first");
  if (!(dt > 0.0)) throw std::invalid_argument("FluidSolver::step: dt must be positive");
  StepReport rep;
  double t0 = now();
  // A moved (not remeshed) mesh keeps its topology: only its geometry is recomputed.
  const bool same_topology = built_from(mesh);
  FluidMesh new_mesh;
  if (same_topology) {
    new_mesh = mesh_;
    update_fluid_mesh_geometry(mesh, new_mesh);
  } else {
    new_mesh = build_fluid_mesh(mesh);
  }
  rep.assemble_seconds += now() - t0;
  t0 = now();
  AdvectionReport adv;
  const BoundaryExits exits = boundary_exits(mesh_, bc);
  fields_ = advect(mesh_, fields_, new_mesh, dt, &adv, params_.advection, &exits);
  set_mesh(mesh, std::move(new_mesh), same_topology);
  advected_velocity_ = fields_.velocity;
  rep.clamped_traces = adv.clamped + adv.outside_start;
  rep.advect_seconds = now() - t0;

  t0 = now();
  boundary_ = classify_boundary(mesh_, bc);
  rep.assemble_seconds += now() - t0;
  t0 = now();
  apply_sources(bc);
  if (params_.apply_gravity)
    for (auto& u : fields_.velocity) u += dt * params_.gravity;
  add_buoyancy(mesh_, fields_.smoke, fields_.temperature, params_.gravity, params_.buoyancy, dt, fields_.velocity);
  add_vorticity_confinement(mesh_, params_.vorticity_epsilon, dt, fields_.velocity);
  rep.forces_seconds = now() - t0;
  return rep;
}

StepReport FluidSolver::apply_pressure(Eigen::VectorXd pressure, double dt, StepReport rep) {
  if (pressure.size() != mesh_.num_nodes())
    throw std::invalid_argument("FluidSolver::apply_pressure: one pressure per fluid node expected");
  pressure_ = std::move(pressure);
  const TetVectors grad_p = gradient(mesh_, pressure_);
  const double scale = dt / params_.density;
  for (int t = 0; t < mesh_.num_tets(); ++t) fields_.velocity[t] -= scale * grad_p[t];
  for (const auto& u : fields_.velocity)
    if (!u.allFinite()) throw std::runtime_error("FluidSolver: velocity became NaN/Inf (diverged)");
  if (!pressure_.allFinite()) throw std::runtime_error("FluidSolver: pressure became NaN/Inf (diverged)");
  rep.num_tets = mesh_.num_tets();
  rep.num_nodes = mesh_.num_nodes();
  rep.kinetic_energy = params_.density * kinetic_energy(mesh_, fields_.velocity);
  return rep;
}

StepReport FluidSolver::project_only(const BoundaryConditions& bc, double dt) {
  if (!initialized_) throw std::logic_error("FluidSolver::project_only: initialize() first");
  const double t0 = now();
  boundary_ = classify_boundary(mesh_, bc);
  StepReport rep;
  rep.assemble_seconds = now() - t0;
  return finish(bc, dt, rep);
}

StepReport FluidSolver::finish(const BoundaryConditions&, double dt, StepReport rep) {
  ProjectionReport pr = project(mesh_, boundary_, dt, params_.density, fields_.velocity, params_.solver);
  pressure_ = std::move(pr.pressure);
  for (const auto& u : fields_.velocity)
    if (!u.allFinite()) throw std::runtime_error("FluidSolver: velocity became NaN/Inf (diverged)");
  if (!pressure_.allFinite()) throw std::runtime_error("FluidSolver: pressure became NaN/Inf (diverged)");
  rep.num_tets = mesh_.num_tets();
  rep.num_nodes = mesh_.num_nodes();
  rep.unknowns = pr.unknowns;
  rep.assemble_seconds += pr.assemble_seconds;
  rep.solve_seconds = pr.solve_seconds;
  rep.iterations = pr.solve.iterations;
  rep.residual = pr.solve.relative_residual;
  rep.max_divergence = pr.max_divergence;
  rep.kinetic_energy = params_.density * kinetic_energy(mesh_, fields_.velocity);
  return rep;
}

Eigen::Vector3d FluidSolver::pressure_force(int subdomain) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const BoundaryFace& bf : mesh_.boundary_faces)
    if (bf.other_subdomain == subdomain)
      f += bf.area * (pressure_[bf.nodes[0]] + pressure_[bf.nodes[1]] + pressure_[bf.nodes[2]]) / 3.0 * bf.normal;
  return f;
}

}  // namespace tetfsi::fluid
