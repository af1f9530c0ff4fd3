#include "coupling/coupled_stepper.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

#include "coupling/interface_maps.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/projection/amg_preconditioner.hpp"
#include "mesh/quality.hpp"

namespace tetfsi::coupling {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Eigen::SparseMatrix<double> block_diagonal(const std::vector<Eigen::SparseMatrix<double>>& blocks) {
  int n = 0;
  std::size_t nnz = 0;
  for (const auto& b : blocks) n += static_cast<int>(b.rows()), nnz += b.nonZeros();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(nnz);
  int offset = 0;
  for (const auto& b : blocks) {
    for (int k = 0; k < b.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(b, k); it; ++it)
        t.emplace_back(offset + it.row(), offset + it.col(), it.value());
    offset += static_cast<int>(b.rows());
  }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

}  // namespace

/// The pieces of eq. (7) for one step, reduced to the pressure unknowns (fluid nodes without a
/// prescribed pressure) and with the fixed solid dofs' flux moved to the right-hand side.
struct CoupledStepper::Blocks {
  CoupledSystem system;
  std::vector<int> unknown;  ///< fluid node -> pressure unknown, -1 where p = 0 is prescribed
};

CoupledStepper::CoupledStepper(mesh::TetMesh mesh, fluid::FluidParams fluid,
                               const std::vector<solid::TetMaterial>& materials, CoupledSettings settings)
    : mesh_(std::move(mesh)), settings_(std::move(settings)), fluid_(std::move(fluid)) {
  if (!(settings_.time_step > 0)) throw std::invalid_argument("coupled step: time step must be positive");
  int offset = 0;
  for (int i = 0; i < static_cast<int>(materials.size()); ++i) {
    Solid s;
    s.submesh = mesh::extract_subdomain(mesh_, mesh::solid_subdomain(i));
    s.model = std::make_unique<solid::TetModel>(s.submesh.mesh, materials[i]);
    solid::TrapezoidalSettings ts;
    ts.time_step = settings_.time_step;
    ts.rayleigh_alpha = materials[i].rayleigh_alpha;
    ts.rayleigh_beta = materials[i].rayleigh_beta;
    ts.gravity = settings_.solid_gravity;
    ts.scheme = settings_.newmark;
    s.integrator = std::make_unique<solid::TrapezoidalIntegrator>(*s.model, ts);
    s.dof_offset = offset;
    offset += 3 * s.model->num_nodes();
    solids_.push_back(std::move(s));
  }
  fluid_.initialize(mesh_);
  CoupledSolverOptions options = settings_.solver_options;
  if (settings_.solver == CoupledSolverKind::SchurCG && fluid_.params().solver.backend == fluid::SolverBackend::kHypreAmgCg &&
      !options.preconditioner_apply) {
    // BoomerAMG of Ŝ = C + H diag(A)⁻¹ Hᵀ, rebuilt each step (the mesh and A change).
    auto amg = std::make_shared<fluid::AmgPreconditioner>();
    options.preconditioner_setup = [amg](const SparseMatrix& S_hat) { amg->setup(S_hat); };
    options.preconditioner_apply = [amg](const Eigen::VectorXd& r, Eigen::VectorXd& z) { amg->apply(r, z); };
    options.preconditioner_name = "boomeramg";
  }
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

MeshUpdateReport CoupledStepper::update_mesh_to_solids() {
  std::vector<Eigen::Vector3d> target = mesh_.vertices;
  for (const Solid& s : solids_) {
    const Eigen::VectorXd x = s.integrator->positions();
    for (int a = 0; a < s.model->num_nodes(); ++a) target[s.submesh.to_parent_vertex[a]] = x.segment<3>(3 * a);
  }
  MeshUpdateResult r = mesh_updater_->update(mesh_, target, min_dihedral_deg_);
  min_dihedral_deg_ = r.report.min_dihedral_deg;
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

CoupledStepper::Blocks CoupledStepper::assemble(double h, CoupledStepReport& report) {
  Blocks blocks;
  CoupledSystem& sys = blocks.system;

  // Solid rows of eq. (4), block-diagonal over the solids.
  auto clock = std::chrono::steady_clock::now();
  std::vector<Eigen::SparseMatrix<double>> A_blocks(solids_.size());
  std::vector<Eigen::VectorXd> b_blocks(solids_.size());
  int n = 0;
  for (std::size_t i = 0; i < solids_.size(); ++i) {
    solids_[i].integrator->form_system(A_blocks[i], b_blocks[i]);
    n += static_cast<int>(b_blocks[i].size());
  }
  sys.A = block_diagonal(A_blocks);
  sys.b.resize(n);
  std::vector<char> fixed(n, 0);
  Eigen::VectorXd fixed_velocity = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i < solids_.size(); ++i) {
    const int o = solids_[i].dof_offset;
    sys.b.segment(o, b_blocks[i].size()) = b_blocks[i];
    const auto& f = solids_[i].integrator->fixed_dofs();
    for (std::size_t k = 0; k < f.size(); ++k)
      if (f[k]) {
        fixed[o + k] = 1;
        // The integrator's Dirichlet rows read A_kk u_k = b_k: the prescribed velocity.
        fixed_velocity[o + k] = b_blocks[i][k] / A_blocks[i].coeff(k, k);
      }
  }
  report.solid_assemble_seconds = seconds_since(clock);
  report.solid_dofs = n;

  // Pressure unknowns: every fluid node without a prescribed pressure.
  clock = std::chrono::steady_clock::now();
  const fluid::FluidMesh& fm = fluid_.mesh();
  const fluid::ClassifiedBoundary& bc = fluid_.boundary();
  blocks.unknown.assign(fm.num_nodes(), -1);
  int m = 0;
  for (int i = 0; i < fm.num_nodes(); ++i)
    if (bc.node_kind[i] != fluid::NodeKind::kOpen) blocks.unknown[i] = m++;

  // H over the interface triangles (interface_maps.hpp), columns of fixed dofs moved to r.
  std::vector<InterfaceTriangle> triangles;
  InterfaceDofs dofs;
  dofs.pressure_index.assign(mesh_.num_vertices(), -1);
  dofs.solid_node.assign(mesh_.num_vertices(), -1);
  for (int i = 0; i < fm.num_nodes(); ++i) dofs.pressure_index[fm.node_to_mesh_vertex[i]] = blocks.unknown[i];
  for (const Solid& s : solids_)
    for (int a = 0; a < s.model->num_nodes(); ++a) dofs.solid_node[s.submesh.to_parent_vertex[a]] = s.dof_offset / 3 + a;
  // With the mean constraint H is taken on the predicted mid-step interface xⁿ + (h/2) uⁿ
  // (CoupledSettings::mean_constraint); the interface vertices are all solid vertices.
  const bool mean = settings_.mean_constraint && settings_.scheme == CouplingScheme::kSimultaneous;
  std::vector<Eigen::Vector3d> mid;
  if (mean) {
    mid = mesh_.vertices;
    for (const Solid& s : solids_) {
      const Eigen::VectorXd q = s.integrator->positions() + 0.5 * h * s.integrator->velocity();
      for (int a = 0; a < s.model->num_nodes(); ++a) mid[s.submesh.to_parent_vertex[a]] = q.segment<3>(3 * a);
    }
  }
  for (const fluid::BoundaryFace& f : fm.boundary_faces) {
    if (f.other_subdomain < mesh::solid_subdomain(0)) continue;
    InterfaceTriangle t;
    for (int k = 0; k < 3; ++k) t.vertices[k] = fm.node_to_mesh_vertex[f.nodes[k]];
    t.area_normal = f.area * f.normal;  // out of the fluid, into the solid
    if (mean) {
      const Eigen::Vector3d& a = mid[t.vertices[0]];
      const Eigen::Vector3d an = 0.5 * (mid[t.vertices[1]] - a).cross(mid[t.vertices[2]] - a);
      t.area_normal = an.dot(f.normal) >= 0 ? an : Eigen::Vector3d(-an);
    }
    triangles.push_back(t);
  }
  report.interface_triangles = static_cast<int>(triangles.size());
  const Eigen::SparseMatrix<double> H_all = interface_flux_map(triangles, dofs, m, n / 3);
  Eigen::VectorXd free_mask = Eigen::VectorXd::Ones(n);
  for (int k = 0; k < n; ++k)
    if (fixed[k]) free_mask[k] = 0;
  sys.H = H_all * free_mask.asDiagonal();
  const Eigen::VectorXd fixed_flux = H_all * fixed_velocity;

  // Fluid rows: C = (h/ρ) L, r = Gᵀ V v* − (prescribed boundary flux) − H_fixed u_fixed.
  const double rho = fluid_.params().density;
  const Eigen::SparseMatrix<double> L = fluid::assemble_laplacian(fm);
  // C is L's rows and columns of the unknowns, scaled. The unknowns are numbered in node order, so
  // L's (sorted, compressed) columns filtered in place are C's columns in order: no sort needed.
  sys.C.resize(m, m);
  sys.C.reserve(L.nonZeros());
  for (int k = 0; k < L.outerSize(); ++k) {
    if (blocks.unknown[k] < 0) continue;
    sys.C.startVec(blocks.unknown[k]);
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, k); it; ++it)
      if (blocks.unknown[it.row()] >= 0) sys.C.insertBack(blocks.unknown[it.row()], blocks.unknown[k]) = (h / rho) * it.value();
  }
  sys.C.finalize();
  const Eigen::VectorXd div_star = fluid::gradient_transpose_volume(fm, fluid_.fields().velocity) - bc.flux;
  sys.r.resize(m);
  for (int i = 0; i < fm.num_nodes(); ++i)
    if (blocks.unknown[i] >= 0) sys.r[blocks.unknown[i]] = div_star[i];
  sys.r -= fixed_flux;
  if (mean) {
    // Gᵀ V v^{n+1} − H u^{n+1} = −(Gᵀ V vⁿ − H uⁿ), vⁿ the advected velocity before body forces:
    // the defect of the start-of-step state on this mesh moves to the right-hand side.
    const Eigen::VectorXd div_n = fluid::gradient_transpose_volume(fm, fluid_.advected_velocity()) - bc.flux;
    Eigen::VectorXd u_n(n);
    for (const Solid& s : solids_) u_n.segment(s.dof_offset, 3 * s.model->num_nodes()) = s.integrator->velocity();
    sys.r -= H_all * u_n;
    for (int i = 0; i < fm.num_nodes(); ++i)
      if (blocks.unknown[i] >= 0) sys.r[blocks.unknown[i]] += div_n[i];
  }

  // A closed fluid region whose boundary cannot move (walls and fixed solids only) has the
  // constant pressure null space: pin one node as the fluid projection does.
  bool moving_boundary = false;
  for (int k = 0; k < sys.H.outerSize() && !moving_boundary; ++k)
    moving_boundary = Eigen::SparseMatrix<double>::InnerIterator(sys.H, k);
  if (bc.closed && !moving_boundary && m > 0) {
    sys.r.array() -= sys.r.mean();
    sys.C.coeffRef(0, 0) += sys.C.coeff(0, 0);  // p_0 anchored softly: unique and still SPD
  }
  report.interface_seconds = seconds_since(clock);
  report.pressure_unknowns = m;
  return blocks;
}

CoupledStepReport CoupledStepper::step(double h) {
  if (!(h > 0)) throw std::invalid_argument("coupled step: time step must be positive");
  for (Solid& s : solids_) s.integrator->set_time_step(h);
  CoupledStepReport report;
  report.mesh_update = update_mesh_to_solids();
  report.fluid = fluid_.predict(mesh_, boundary_, h);
  Blocks blocks = assemble(h, report);
  CoupledSystem& sys = blocks.system;
  const int n = sys.num_solid_dofs(), m = sys.num_pressures();

  Eigen::VectorXd u, p;
  if (settings_.scheme == CouplingScheme::kSimultaneous) {
    // Initial guess of the iterative solvers: the previous step's pressure (carried per mesh
    // vertex through remeshing) and the current solid velocities.
    p = Eigen::VectorXd::Zero(m);
    for (int i = 0; i < static_cast<int>(blocks.unknown.size()); ++i)
      if (blocks.unknown[i] >= 0) p[blocks.unknown[i]] = previous_vertex_pressure_[fluid_.mesh().node_to_mesh_vertex[i]];
    u.resize(n);
    for (const Solid& s : solids_) u.segment(s.dof_offset, 3 * s.model->num_nodes()) = s.integrator->velocity();
    report.solve = solver_->solve(sys, u, p);
  } else {
    // Time splitting: solid with the previous pressure, then fluid with the new solid velocity.
    Eigen::VectorXd p_old = Eigen::VectorXd::Zero(m);
    for (int i = 0; i < static_cast<int>(blocks.unknown.size()); ++i)
      if (blocks.unknown[i] >= 0)
        p_old[blocks.unknown[i]] = previous_vertex_pressure_[fluid_.mesh().node_to_mesh_vertex[i]];
    CoupledSystem solid_only{sys.A, Eigen::SparseMatrix<double>(0, n), Eigen::SparseMatrix<double>(0, 0),
                             sys.b + sys.H.transpose() * p_old, Eigen::VectorXd(0)};
    Eigen::VectorXd unused;
    const CoupledSolveReport rs = solver_->solve(solid_only, u, unused);
    CoupledSystem fluid_only{Eigen::SparseMatrix<double>(0, 0), Eigen::SparseMatrix<double>(m, 0), sys.C,
                             Eigen::VectorXd(0), sys.r - sys.H * u};
    Eigen::VectorXd none;
    report.solve = solver_->solve(fluid_only, none, p);
    report.solve.solver = "splitting:" + report.solve.solver;
    report.solve.iterations += rs.iterations;
    report.solve.setup_seconds += rs.setup_seconds;
    report.solve.solve_seconds += rs.solve_seconds;
    report.solve.residual = residuals(sys, u, p);  // of the coupled equations: shows the splitting error
  }
  if (!u.allFinite() || !p.allFinite())
    throw std::runtime_error("coupled step " + std::to_string(step_ + 1) + ": solution is not finite (diverged)");

  Eigen::VectorXd pressure = Eigen::VectorXd::Zero(fluid_.mesh().num_nodes());
  for (int i = 0; i < pressure.size(); ++i)
    if (blocks.unknown[i] >= 0) pressure[i] = p[blocks.unknown[i]];
  for (int i = 0; i < pressure.size(); ++i)
    previous_vertex_pressure_[fluid_.mesh().node_to_mesh_vertex[i]] = pressure[i];
  report.fluid = fluid_.apply_pressure(std::move(pressure), h, report.fluid);
  report.fluid.solve_seconds = report.solve.setup_seconds + report.solve.solve_seconds;
  report.fluid.iterations = report.solve.iterations;

  for (Solid& s : solids_) {
    s.integrator->advance(u.segment(s.dof_offset, 3 * s.model->num_nodes()));
    const solid::StepStats e = s.integrator->energies();
    report.solid_kinetic += e.kinetic;
    report.solid_strain += e.strain;
    report.spring_energy += e.spring;
    report.solid_gravity_potential += e.gravity_potential;
  }
  report.fluid_kinetic = report.fluid.kinetic_energy;
  time_ += h;
  report.step = ++step_;
  report.time = time_;
  return report;
}

double CoupledStepper::fluid_volume() const {
  std::vector<Eigen::Vector3d> x = mesh_.vertices;
  for (const Solid& s : solids_) {
    const Eigen::VectorXd q = s.integrator->positions();
    for (int a = 0; a < s.model->num_nodes(); ++a) x[s.submesh.to_parent_vertex[a]] = q.segment<3>(3 * a);
  }
  double volume = 0;
  for (int t = 0; t < mesh_.num_tets(); ++t) {
    if (!mesh_.subdomain.empty() && mesh_.subdomain[t] != mesh::kFluidSubdomain) continue;
    const auto& v = mesh_.tets[t];
    volume += mesh::signed_volume(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
  }
  return volume;
}

}  // namespace tetfsi::coupling
