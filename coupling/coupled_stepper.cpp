#include "coupling/coupled_stepper.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "coupling/interface_maps.hpp"
#include "fluid/liquid/cut_tet.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/projection/amg_preconditioner.hpp"
#include "parallel/distributed_solve.hpp"
#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/quality.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::coupling {
namespace {

/// diag(blocks[0], blocks[1], ...), the blocks' compressed columns placed one after the other (no
/// triplets, no sort); the blocks are consumed (one block is swapped out, not copied).
SparseMatrix block_diagonal(std::vector<SparseMatrix>& blocks) {
  SparseMatrix m;
  if (blocks.size() == 1) {
    blocks[0].makeCompressed();
    m.swap(blocks[0]);
    return m;
  }
  int n = 0;
  Eigen::Index nnz = 0;
  for (auto& b : blocks) {
    b.makeCompressed();
    n += static_cast<int>(b.rows()), nnz += b.nonZeros();
  }
  m.resize(n, n);
  m.resizeNonZeros(nnz);
  int offset = 0, column = 0;
  Eigen::Index entry = 0;
  for (auto& b : blocks) {
    for (int k = 0; k < b.outerSize(); ++k, ++column) {
      m.outerIndexPtr()[column] = static_cast<int>(entry);
      for (int e = b.outerIndexPtr()[k]; e < b.outerIndexPtr()[k + 1]; ++e, ++entry) {
        m.innerIndexPtr()[entry] = offset + b.innerIndexPtr()[e];
        m.valuePtr()[entry] = b.valuePtr()[e];
      }
    }
    offset += static_cast<int>(b.rows());
    b = SparseMatrix();
  }
  m.outerIndexPtr()[n] = static_cast<int>(entry);
  return m;
}

}  // namespace

/// The solid rows of eq. (4) for one step, block-diagonal over the solids.
struct CoupledStepper::SolidRows {
  SparseMatrix A;                  ///< n x n, Dirichlet dofs eliminated (rows A_kk u_k = b_k)
  Eigen::VectorXd b;               ///< n
  std::vector<char> fixed;         ///< per solid dof: velocity prescribed
  Eigen::VectorXd fixed_velocity;  ///< the prescribed velocity of fixed dofs, 0 elsewhere
};

/// The fluid rows of eq. (6) for one step, on the pressure unknowns.
struct CoupledStepper::FluidRows {
  SparseMatrix P;     ///< m x m, (h/ρ) L
  Eigen::VectorXd r;  ///< m, Gᵀ V v* less the prescribed fluxes
};

/// The interface maps of sec. 3.4 for one step, on the pressure unknowns (fluid nodes without a
/// prescribed pressure).
struct CoupledStepper::Interface {
  std::vector<int> unknown;  ///< fluid node -> pressure unknown, -1 where p = 0 is prescribed
  SparseMatrix H_all;        ///< m x n, every solid dof
  SparseMatrix H;            ///< H_all with the fixed dofs' columns zeroed (J = Hᵀ)
  Eigen::VectorXd fixed_flux;  ///< H_all u_fixed, the flux of the prescribed velocities, moved to r
};

CoupledStepper::CoupledStepper(mesh::TetMesh mesh, fluid::FluidParams fluid,
                               const std::vector<solid::TetMaterial>& materials, CoupledSettings settings,
                               const std::vector<solid::TetModelOptions>& model_options)
    : mesh_(std::move(mesh)), settings_(std::move(settings)), fluid_(std::move(fluid)) {
  if (!model_options.empty() && model_options.size() != materials.size())
    throw std::invalid_argument("coupled step: one element option set per solid expected");
  int offset = 0;
  for (int i = 0; i < static_cast<int>(materials.size()); ++i) {
    Solid s;
    s.submesh = mesh::extract_subdomain(mesh_, mesh::solid_subdomain(i));
    s.model = std::make_unique<solid::TetModel>(s.submesh.mesh, materials[i],
                                                model_options.empty() ? solid::TetModelOptions{} : model_options[i]);
    solid::NewmarkSettings ts;
    ts.rayleigh_alpha = materials[i].rayleigh_alpha;
    ts.rayleigh_beta = materials[i].rayleigh_beta;
    ts.gravity = settings_.solid_gravity;
    ts.scheme = settings_.newmark;
    s.integrator = std::make_unique<solid::NewmarkIntegrator>(*s.model, ts);
    s.dof_offset = offset;
    offset += 3 * s.model->num_nodes();
    solids_.push_back(std::move(s));
  }
  num_solid_dofs_ = offset;
  fluid_.initialize(mesh_);
  CoupledSolverOptions options = settings_.solver_options;
  const fluid::SolverBackend pressure_backend = fluid_.params().solver.backend;
  if (settings_.solver == CoupledSolverKind::SchurCG && !options.preconditioner_apply) {
    // BoomerAMG of Ŝ = P + H diag(A)⁻¹ Hᵀ, rebuilt each step (the mesh and A change): hypre's on
    // this process, or PETSc's over the MPI processes of the run (parallel/distributed_solve.hpp).
    if (pressure_backend == fluid::SolverBackend::kHypreAmgCg) {
      auto amg = std::make_shared<fluid::AmgPreconditioner>();
      options.preconditioner_setup = [amg](const SparseMatrix& S_hat) { amg->setup(S_hat); };
      options.preconditioner_apply = [amg](const Eigen::VectorXd& r, Eigen::VectorXd& z) { amg->apply(r, z); };
      options.preconditioner_name = "boomeramg";
    } else if (pressure_backend == fluid::SolverBackend::kPetscAmgCg) {
      auto amg = std::make_shared<parallel::DistributedAmg>();
      options.preconditioner_setup = [amg](const SparseMatrix& S_hat) { amg->setup(S_hat); };
      options.preconditioner_apply = [amg](const Eigen::VectorXd& r, Eigen::VectorXd& z) { amg->apply(r, z); };
      options.preconditioner_name = "petsc_boomeramg";
    }
  }
  if (!settings_.compare_solvers.empty())
    comparison_ = std::make_unique<SolverComparison>(settings_.compare_solvers, options, fluid_.params().solver);
  solver_ = make_coupled_solver(settings_.solver, std::move(options));
  previous_vertex_pressure_.assign(mesh_.num_vertices(), 0.0);
  min_dihedral_deg_ = mesh::quality_report(mesh_, mesh::kFluidSubdomain).min_dihedral_deg;
  if (!(settings_.mesh_update.remesh.target_edge_length > 0))
    settings_.mesh_update.remesh.target_edge_length = fluid_edge_length_near_solids(mesh_);
  // Remeshing the whole of a graded fluid at its near-solid size multiplies the tet count (a bar
  // scene went from 6k to 141k tets in one remesh): no band means four near-solid cells.
  if (!(settings_.mesh_update.remesh.band > 0))
    settings_.mesh_update.remesh.band = 4 * settings_.mesh_update.remesh.target_edge_length;
  mesh_updater_ = std::make_unique<MeshUpdater>(settings_.mesh_update);
}

void CoupledStepper::set_size_field(SizeFieldRequest request) { mesh_updater_->set_size_field(std::move(request)); }

MeshUpdateReport CoupledStepper::update_mesh_to_solids() {
  MeshUpdateResult r = mesh_updater_->update(mesh_, mesh_vertices_at(solid_positions()), min_dihedral_deg_);
  min_dihedral_deg_ = r.report.min_dihedral_deg;
  fluid_mesh_moved_vertices_ = std::move(r.moved_vertices);
  if (r.report.remeshed) {
    // Solid vertices are never removed by the remesher: renumber the solid-node maps and carry
    // the previous pressure of kept vertices (the interface ones are all kept).
    std::vector<int> new_index(mesh_.num_vertices(), -1);
    std::vector<double> pressure(r.mesh.num_vertices(), 0.0);
    for (int v = 0; v < r.mesh.num_vertices(); ++v)
      if (r.old_index[v] >= 0) {
        new_index[r.old_index[v]] = v;
        pressure[v] = previous_vertex_pressure_[r.old_index[v]];
      }
    for (Solid& s : solids_) {
      for (int& v : s.submesh.to_parent_vertex) {
        v = new_index[v];
        if (v < 0) throw std::logic_error("coupled step: the remesher dropped a solid vertex");
      }
      s.submesh.from_parent_vertex.assign(r.mesh.num_vertices(), -1);
      for (int a = 0; a < static_cast<int>(s.submesh.to_parent_vertex.size()); ++a)
        s.submesh.from_parent_vertex[s.submesh.to_parent_vertex[a]] = a;
      s.submesh.to_parent_tet.clear();  // tet numbering of the remeshed complex differs; unused here
    }
    previous_vertex_pressure_ = std::move(pressure);
  }
  mesh_ = std::move(r.mesh);
  return r.report;
}

std::vector<Eigen::Vector3d> CoupledStepper::fluid_node_positions() const {
  const fluid::FluidMesh& fm = fluid_.mesh();
  if (fluid_mesh_moved_vertices_.empty()) return fm.nodes;
  std::vector<Eigen::Vector3d> x(fm.num_nodes());
  for (int i = 0; i < fm.num_nodes(); ++i) x[i] = fluid_mesh_moved_vertices_[fm.node_to_mesh_vertex[i]];
  return x;
}

Eigen::VectorXd CoupledStepper::solid_positions() const {
  Eigen::VectorXd x(num_solid_dofs_);
  for (const Solid& s : solids_) x.segment(s.dof_offset, 3 * s.model->num_nodes()) = s.integrator->positions();
  return x;
}

Eigen::VectorXd CoupledStepper::solid_velocities() const {
  Eigen::VectorXd u(num_solid_dofs_);
  for (const Solid& s : solids_) u.segment(s.dof_offset, 3 * s.model->num_nodes()) = s.integrator->velocity();
  return u;
}

std::vector<Eigen::Vector3d> CoupledStepper::mesh_vertices_at(const Eigen::VectorXd& solid_x) const {
  std::vector<Eigen::Vector3d> x = mesh_.vertices;
  for (const Solid& s : solids_)
    for (int a = 0; a < s.model->num_nodes(); ++a)
      x[s.submesh.to_parent_vertex[a]] = solid_x.segment<3>(s.dof_offset + 3 * a);
  return x;
}

Eigen::VectorXd CoupledStepper::previous_pressure(const std::vector<int>& unknown, int m) const {
  Eigen::VectorXd p = Eigen::VectorXd::Zero(m);
  for (int i = 0; i < static_cast<int>(unknown.size()); ++i)
    if (unknown[i] >= 0) p[unknown[i]] = previous_vertex_pressure_[fluid_.mesh().node_to_mesh_vertex[i]];
  return p;
}

bool CoupledStepper::mean_constraint() const {
  return settings_.mean_constraint && settings_.scheme == CouplingScheme::kSimultaneous && !fluid_.has_free_surface();
}

CoupledStepper::SolidRows CoupledStepper::assemble_solid_rows(double h, CoupledStepReport& report) {
  const Stopwatch clock;
  SolidRows rows;
  std::vector<SparseMatrix> A_blocks(solids_.size());
  std::vector<Eigen::VectorXd> b_blocks(solids_.size());
  for (std::size_t i = 0; i < solids_.size(); ++i) {
    solids_[i].integrator->form_system(h, A_blocks[i], b_blocks[i]);
    solids_[i].model->release_workspace();  // not kept through the rest of the step (its peak memory)
  }
  const int n = num_solid_dofs_;
  rows.b.resize(n);
  rows.fixed.assign(n, 0);
  rows.fixed_velocity = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i < solids_.size(); ++i) {
    const int o = solids_[i].dof_offset;
    rows.b.segment(o, b_blocks[i].size()) = b_blocks[i];
    const auto& f = solids_[i].integrator->fixed_dofs();
    for (std::size_t k = 0; k < f.size(); ++k)
      if (f[k]) {
        rows.fixed[o + k] = 1;
        // The integrator's Dirichlet rows read A_kk u_k = b_k: the prescribed velocity.
        rows.fixed_velocity[o + k] = b_blocks[i][k] / A_blocks[i].coeff(k, k);
      }
  }
  rows.A = block_diagonal(A_blocks);  // after the reads of A_blocks above: it consumes them
  report.solid_assemble_seconds = clock.seconds();
  report.solid_dofs = n;
  return rows;
}

void CoupledStepper::add_viscous_drag(SolidRows& rows) {
  const fluid::FluidMesh& fm = fluid_.mesh();
  const std::vector<Eigen::Vector3d>& force = fluid_.viscous_node_force();
  const std::vector<Eigen::Matrix3d>& stiffness = fluid_.viscous_node_stiffness();
  if (force.empty()) return;
  std::vector<int> solid_dof(mesh_.num_vertices(), -1);  // mesh vertex -> first dof of its solid node
  for (const Solid& s : solids_)
    for (int a = 0; a < s.model->num_nodes(); ++a) solid_dof[s.submesh.to_parent_vertex[a]] = s.dof_offset + 3 * a;
  const Eigen::VectorXd u = solid_velocities();
  viscous_force_.assign(solids_.size(), Eigen::Vector3d::Zero());
  for (int i = 0; i < fm.num_nodes(); ++i) {
    const int d = solid_dof[fm.node_to_mesh_vertex[i]];
    if (d < 0 || force[i].isZero(0.0)) continue;
    for (std::size_t k = 0; k < solids_.size(); ++k)
      if (d >= solids_[k].dof_offset && d < solids_[k].dof_offset + 3 * solids_[k].model->num_nodes())
        viscous_force_[k] += force[i];
    // F(u^{n+1}) ~ F(uⁿ) - C (u^{n+1} - uⁿ): A += C, b += F(uⁿ) + C uⁿ on the free dofs (A and b
    // are eq. (18)'s, forces per unit time: A = M/h + ..., b = (M/h) uⁿ + ... + f).
    const Eigen::Vector3d b = force[i] + stiffness[i] * u.segment<3>(d);
    for (int a = 0; a < 3; ++a) {
      if (rows.fixed[d + a]) continue;
      rows.b[d + a] += b[a];
      for (int c = 0; c < 3; ++c)
        if (!rows.fixed[d + c] && stiffness[i](a, c) != 0) rows.A.coeffRef(d + a, d + c) += stiffness[i](a, c);
    }
  }
}

std::vector<int> CoupledStepper::pressure_unknowns(int& count) const {
  const fluid::FluidMesh& fm = fluid_.mesh();
  std::vector<int> unknown(fm.num_nodes(), -1);
  const bool surface = free_surface();
  count = 0;
  for (int i = 0; i < fm.num_nodes(); ++i)
    if (fluid_.boundary().node_kind[i] != fluid::NodeKind::kOpen && (!surface || fluid_.liquid().is_liquid[i]))
      unknown[i] = count++;
  return unknown;
}

std::vector<int> CoupledStepper::solid_node_of_vertex() const {
  std::vector<int> node(mesh_.num_vertices(), -1);
  for (const Solid& s : solids_)
    for (int a = 0; a < s.model->num_nodes(); ++a) node[s.submesh.to_parent_vertex[a]] = s.dof_offset / 3 + a;
  return node;
}

CoupledStepper::Interface CoupledStepper::assemble_interface(double h, const SolidRows& solid,
                                                             CoupledStepReport& report) const {
  const fluid::FluidMesh& fm = fluid_.mesh();
  const int n = num_solid_dofs_;
  Interface interface;
  int m = 0;
  interface.unknown = pressure_unknowns(m);
  const bool surface = free_surface();

  InterfaceDofs dofs;
  dofs.pressure_index.assign(mesh_.num_vertices(), -1);
  dofs.solid_node = solid_node_of_vertex();
  for (int i = 0; i < fm.num_nodes(); ++i) dofs.pressure_index[fm.node_to_mesh_vertex[i]] = interface.unknown[i];
  // With the mean constraint H is taken on the predicted mid-step interface xⁿ + (h/2) uⁿ
  // (CoupledSettings::mean_constraint); the interface vertices are all solid vertices.
  const bool mean = mean_constraint();
  std::vector<Eigen::Vector3d> mid;
  if (mean) mid = mesh_vertices_at(solid_positions() + 0.5 * h * solid_velocities());
  std::vector<InterfaceTriangle> triangles;
  for (const fluid::BoundaryFace& f : fm.boundary_faces) {
    if (f.other_subdomain < mesh::solid_subdomain(0)) continue;
    InterfaceTriangle t;
    for (int k = 0; k < 3; ++k) t.vertices[k] = fm.node_to_mesh_vertex[f.nodes[k]];
    t.area_normal = f.area * f.normal;  // out of the fluid, into the solid
    if (surface) {  // the pressure on the wet part only, as in the liquid's rows (interface_maps.hpp)
      const Eigen::VectorXd& phi = fluid_.level_set();
      t.mass = fluid::wet_face_mass({phi[f.nodes[0]], phi[f.nodes[1]], phi[f.nodes[2]]});
    }
    if (mean) {
      const Eigen::Vector3d& a = mid[t.vertices[0]];
      const Eigen::Vector3d an = 0.5 * (mid[t.vertices[1]] - a).cross(mid[t.vertices[2]] - a);
      t.area_normal = an.dot(f.normal) >= 0 ? an : Eigen::Vector3d(-an);
    }
    triangles.push_back(t);
  }
  report.interface_triangles = static_cast<int>(triangles.size());
  // J = Hᵀ; the columns of fixed dofs move to the right-hand side as the flux H_fixed u_fixed.
  interface.H_all = interface_flux_map(triangles, dofs, m, n / 3);
  Eigen::VectorXd free_mask = Eigen::VectorXd::Ones(n);
  for (int k = 0; k < n; ++k)
    if (solid.fixed[k]) free_mask[k] = 0;
  interface.H = interface.H_all * free_mask.asDiagonal();
  interface.fixed_flux = interface.H_all * solid.fixed_velocity;
  return interface;
}

CoupledStepper::FluidRows CoupledStepper::assemble_fluid_rows(double h, const Interface& interface) {
  const fluid::FluidMesh& fm = fluid_.mesh();
  const fluid::ClassifiedBoundary& bc = fluid_.boundary();
  const std::vector<int>& unknown = interface.unknown;
  const int m = static_cast<int>(interface.H_all.rows());
  FluidRows rows;
  const double rho = fluid_.params().density;
  if (free_surface()) {
    // The liquid's rows (free_surface_projection.hpp): P = (h/ρ) Bᵀ W B, r = Σ_t a_i·v*_t − f_i −
    // H_fixed u_fixed on the liquid nodes; the air is void, p = 0 on the surface.
    const fluid::LiquidGeometry& liquid = fluid_.liquid();
    rows.P = (h / rho) * fluid::wet_laplacian(fm, liquid, unknown, m);
    const Eigen::VectorXd div_star = fluid::wet_gradient_transpose(fm, liquid, fluid_.fields().velocity) - bc.flux;
    rows.r.resize(m);
    for (int i = 0; i < fm.num_nodes(); ++i)
      if (unknown[i] >= 0) rows.r[unknown[i]] = div_star[i];
    rows.r -= interface.fixed_flux;
    return rows;
  }
  // P = (h/ρ) L on the unknowns, r = Gᵀ V v* − (prescribed boundary flux) − H_fixed u_fixed.
  rows.P = fluid::assemble_laplacian(fm, unknown, m, h / rho, &fluid_rows_pattern_);
  const Eigen::VectorXd div_star = fluid::gradient_transpose_volume(fm, fluid_.fields().velocity) - bc.flux;
  rows.r.resize(m);
  for (int i = 0; i < fm.num_nodes(); ++i)
    if (unknown[i] >= 0) rows.r[unknown[i]] = div_star[i];
  rows.r -= interface.fixed_flux;
  if (mean_constraint()) {
    // Gᵀ V v^{n+1} − H u^{n+1} = −(Gᵀ V vⁿ − H uⁿ), vⁿ the advected velocity before body forces:
    // the defect of the start-of-step state on this mesh moves to the right-hand side.
    const Eigen::VectorXd div_n = fluid_.advected_divergence() - bc.flux;
    rows.r -= interface.H_all * solid_velocities();
    for (int i = 0; i < fm.num_nodes(); ++i)
      if (unknown[i] >= 0) rows.r[unknown[i]] += div_n[i];
  }

  // A closed fluid region whose boundary cannot move (walls and fixed solids only) has the
  // constant pressure null space: pin one node as the fluid projection does.
  bool moving_boundary = false;
  for (int k = 0; k < interface.H.outerSize() && !moving_boundary; ++k)
    moving_boundary = SparseMatrix::InnerIterator(interface.H, k);
  if (bc.closed && !moving_boundary && m > 0) {
    rows.r.array() -= rows.r.mean();
    rows.P.coeffRef(0, 0) += rows.P.coeff(0, 0);  // p_0 anchored softly: unique and still SPD
  }
  return rows;
}

CoupledSolveReport CoupledStepper::solve(const CoupledSystem& sys, const std::vector<int>& unknown,
                                         Eigen::VectorXd& u, Eigen::VectorXd& p) {
  const int n = sys.num_solid_dofs(), m = sys.num_pressures();
  CoupledSolveReport report;
  if (settings_.scheme == CouplingScheme::kSimultaneous) {
    // Initial guess of the iterative solvers: the previous step's pressure (carried per mesh
    // vertex through remeshing) and the current solid velocities.
    p = previous_pressure(unknown, m);
    u = solid_velocities();
    report = solver_->solve(sys, u, p);
  } else {
    // Time splitting: solid with the previous pressure, then fluid with the new solid velocity.
    const Eigen::VectorXd p_old = previous_pressure(unknown, m);
    CoupledSystem solid_only{sys.A, SparseMatrix(0, n), SparseMatrix(0, 0), sys.b + sys.H.transpose() * p_old,
                             Eigen::VectorXd(0)};
    Eigen::VectorXd unused;
    const CoupledSolveReport rs = solver_->solve(solid_only, u, unused);
    CoupledSystem fluid_only{SparseMatrix(0, 0), SparseMatrix(m, 0), sys.P, Eigen::VectorXd(0), sys.r - sys.H * u};
    Eigen::VectorXd none;
    report = solver_->solve(fluid_only, none, p);
    report.solver = "splitting:" + report.solver;
    report.iterations += rs.iterations;
    report.setup_seconds += rs.setup_seconds;
    report.solve_seconds += rs.solve_seconds;
    report.residual = residuals(sys, u, p);  // of the coupled equations: shows the splitting error
  }
  if (!u.allFinite() || !p.allFinite())
    throw std::runtime_error("coupled step " + std::to_string(step_ + 1) + ": solution is not finite (diverged)");
  return report;
}

void CoupledStepper::update(double h, const Eigen::VectorXd& u, const Eigen::VectorXd& p,
                            const std::vector<int>& unknown, CoupledStepReport& report) {
  // Eq. (8): the fluid velocity from the new pressure.
  Eigen::VectorXd pressure = Eigen::VectorXd::Zero(fluid_.mesh().num_nodes());
  for (int i = 0; i < pressure.size(); ++i)
    if (unknown[i] >= 0) pressure[i] = p[unknown[i]];
  for (int i = 0; i < pressure.size(); ++i)
    previous_vertex_pressure_[fluid_.mesh().node_to_mesh_vertex[i]] = pressure[i];
  report.fluid = fluid_.apply_pressure(std::move(pressure), h, report.fluid);
  report.fluid.solve_seconds = report.solve.setup_seconds + report.solve.solve_seconds;
  report.fluid.iterations = report.solve.iterations;
  report.fluid_kinetic = report.fluid.kinetic_energy;
  // Eq. (5): the solid displacement from the new velocity.
  for (Solid& s : solids_) {
    s.integrator->advance(h, u.segment(s.dof_offset, 3 * s.model->num_nodes()));
    report.obstacle_clearance = std::min(report.obstacle_clearance, s.integrator->obstacle_clearance());
    const solid::StepStats e = s.integrator->energies();
    report.solid_kinetic += e.kinetic;
    report.solid_strain += e.strain;
    report.spring_energy += e.spring;
    report.solid_gravity_potential += e.gravity_potential;
  }
}

CoupledStepReport CoupledStepper::step_once(double h, bool guard_energy) {
  CoupledStepReport report;
  report.min_substep = h;
  if (settings_.before_step) settings_.before_step(time_, h);  // kinematic solids' velocities
  // A viscous fluid sticks to the solids at their velocity uⁿ (fluid/viscosity/viscous_boundary.hpp).
  if (fluid_.viscous()) boundary_.no_slip_velocity = mesh_vertices_at(solid_velocities());
  fluid_.keep_advected_divergence(mean_constraint());  // read by assemble_fluid_rows
  report.fluid = fluid_.predict(mesh_, boundary_, h);  // v*: advection, viscosity, body forces
  {
    int num_unknowns = 0;
    begin_closed_volumes(h, pressure_unknowns(num_unknowns), report);  // uⁿ keeps the closed volumes
    // The step's rows and system live in this block only, so that they are freed before the mesh
    // update (whose factorization of the mesh motion, at the second step on a mesh, is the step's
    // largest allocation).
    SolidRows solid = assemble_solid_rows(h, report);    // eq. (4): A, b
    if (fluid_.viscous()) add_viscous_drag(solid);
    const Stopwatch clock;
    Interface interface = assemble_interface(h, solid, report);   // sec. 3.4: H, J = Hᵀ
    FluidRows fluid = assemble_fluid_rows(h, interface);          // eq. (6): (h/ρ) L, r
    Eigen::VectorXd volume_source = Eigen::VectorXd::Zero(fluid.r.size());  // V(x^{n+1}) = V₀ in each closed region
    if (!closed_volumes_.regions().empty())
      closed_volumes_.add_volume_source(h, fluid_.mesh(), interface.unknown, volume_source, report.closed_volume);
    fluid.r += volume_source;
    // Swapped, not moved: Eigen 3.4's SparseMatrix has no move constructor, and a copy of A, H and P
    // would stay in memory for the whole step.
    CoupledSystem sys;
    sys.A.swap(solid.A);
    sys.H.swap(interface.H);
    sys.P.swap(fluid.P);
    sys.b = std::move(solid.b);
    sys.r = std::move(fluid.r);
    report.interface_seconds = clock.seconds();
    report.pressure_unknowns = sys.num_pressures();
    Eigen::VectorXd u, p;
    report.solve = solve_with_contact(h, sys, interface.unknown, u, p);  // eq. (7) with contact
    restore_closed_volumes(h, sys, interface.unknown, u, p, report);     // V(x^{n+1}) = V₀
    if (comparison_) {  // eq. (7) of the same step from the same guess, before update() moves either
      sys.r -= volume_source;  // the fluid-only projection has the solids as walls: no dilatation
      report.compared =
          comparison_->run(sys, solid_velocities(), previous_pressure(interface.unknown, sys.num_pressures()));
      sys.r += volume_source;
    }
    const Eigen::VectorXd pressure_forces = interface.H_all.transpose() * p;  // J p^{n+1}, fixed nodes too
    pressure_force_.assign(solids_.size(), Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < solids_.size(); ++i)
      for (int a = 0; a < solids_[i].model->num_nodes(); ++a)
        pressure_force_[i] += pressure_forces.segment<3>(solids_[i].dof_offset + 3 * a);
    update(h, u, p, interface.unknown, report);                         // eqs. (8) and (5)
    if (!closed_volumes_.regions().empty())
      report.closed_volume_error = closed_volumes_.relative_error(mesh_vertices_at(solid_positions()));
    if (guard_energy && energy_guard_gain_ > 0) {
      report.fluid_gravity_potential = fluid_gravity_potential(report);  // as after the mesh update
      if (report.total_energy() - energy_guard_energy_ > energy_guard_gain_)
        throw EnergyGainError("coupled step: the energy rose by " +
                              std::to_string(report.total_energy() - energy_guard_energy_) + " J");
    }
    fluid_rows_pattern_.swap(sys.P);
  }
  report.mesh_update = update_mesh_to_solids();  // x^{n+1}: the fluid mesh follows the solids
  report.fluid_gravity_potential = fluid_gravity_potential(report);
  time_ += h;
  report.step = ++step_;
  report.time = time_;
  return report;
}

bool CoupledStepper::free_surface() const {
  return fluid_.has_free_surface() && fluid_.liquid().num_air_nodes > 0;
}

}  // namespace tetfsi::coupling
