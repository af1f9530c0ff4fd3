#pragma once
/// @file fluid_solver.hpp
/// One time step of the incompressible fluid (inviscid or viscous) on a (possibly new) tetrahedral mesh:
///   1. advect velocity, smoke and temperature from the previous mesh to this one
///      (semi_lagrangian.hpp; skipped on the first step),
///   2. sources: emitter volumes and inflow patches set smoke and temperature; with a free
///      surface both add liquid (an inflow patch keeps the layer one edge deep in front of it full
///      of liquid at its velocity),
///   2b. viscosity, if any (implicit_viscosity.hpp), on the advected field,
///   3. body forces: gravity, buoyancy, optional vorticity confinement (body_forces.hpp),
///   4. projection with the boundary conditions of this step (projection.hpp).
/// Kinematic solids enter through BoundaryConditions::solid_vertex_velocity.
#include <Eigen/Core>
#include <memory>

#include "fluid/advection/semi_lagrangian.hpp"
#include "fluid/boundary/boundary_conditions.hpp"
#include "fluid/forces/body_forces.hpp"
#include "fluid/liquid/free_surface_projection.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/particles/particles.hpp"
#include "fluid/projection/projection.hpp"
#include "fluid/viscosity/implicit_viscosity.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

namespace tetfsi::fluid {

struct FluidParams {
  double density = 1.0;                                    ///< rho [kg/m^3]
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.81);  ///< [m/s^2]; also the buoyancy direction
  bool apply_gravity = true;  ///< add g to u (smoke scenes may leave it off: it only adds hydrostatic p)
  BuoyancyParams buoyancy;
  double vorticity_epsilon = 0.0;
  AdvectionScheme advection = AdvectionScheme::kLinear;  ///< see semi_lagrangian.hpp and the TG test
  /// Velocity carried on particles (APIC or FLIP, particles/particles.hpp) instead of by `advection`,
  /// which then carries only smoke and temperature (and the velocity of a smoke's tets without particles).
  ParticleOptions particles;
  SolverOptions solver;
  /// Dynamic viscosity mu [Pa s]; > 0: the implicit viscous step of implicit_viscosity.hpp before
  /// the body forces; 0: inviscid (no viscous step, bit-identical to a solver without one).
  double viscosity = 0.0;
  /// Boxes of other viscosity: a tet whose centroid lies in one takes its viscosity (first match).
  std::vector<std::pair<Region, double>> viscosity_regions;
  WallCondition walls = WallCondition::kNoSlip;  ///< tangential condition of walls and solids (viscous only)
  /// Tolerance and iteration limit of the viscous step's CG (Jacobi-preconditioned, matrix-free:
  /// implicit_viscosity.hpp; the backend is not read).
  SolverOptions viscous_solver{SolverBackend::kEigenIcCg, 1e-8, 2000};
};

/// Free-surface liquid (liquid/level_set.hpp): how the level set is kept.
struct LiquidOptions {
  double band = 0.0;            ///< |phi| is the distance to the surface up to this [m] (> 0)
  int extension_layers = 4;     ///< layers of air tets that receive the liquid's velocity
  /// Cut tets with less liquid than this fraction of their volume take the extended velocity of
  /// their neighbours after the projection instead of their own (see fluid/README.md, "Liquids").
  double min_kept_fraction = 0.1;
  /// Weight of a tet in the advection's node averages: max(|Omega_t|, air_weight V_t).
  double air_weight = 1e-3;
  bool restore_volume = true;   ///< shift phi each step so that the liquid keeps its volume
  /// Advect phi with BFECC (advect_nodal_bfecc: thin sheets and drops last far longer) instead of
  /// first-order semi-Lagrangian interpolation (advect_nodal).
  bool bfecc = false;
};

/// Per-step statistics (one stats.csv row).
struct StepReport {
  int num_tets = 0, num_nodes = 0, unknowns = 0;
  double advect_seconds = 0.0;    ///< back-tracing and interpolation
  double assemble_seconds = 0.0;  ///< fluid mesh geometry, boundary classification, L and rhs
  double solve_seconds = 0.0;     ///< pressure solve (set-up + iterations)
  double forces_seconds = 0.0;
  double viscosity_seconds = 0.0; ///< the implicit viscous step (0 when inviscid)
  int viscous_iterations = 0;     ///< CG iterations of the viscous step
  int iterations = 0;
  double residual = 0.0;          ///< true relative residual of the pressure solve
  double max_divergence = 0.0;    ///< max |weak div| / dual volume after projection [1/s]
  int clamped_traces = 0;
  double kinetic_energy = 0.0;    ///< 1/2 rho sum V_t |u_t|^2 after the step [J] (liquid: its part |Omega_t|)
  /// -rho g . int x dV over the fluid (liquid: its part) after the step [J]; 0 without gravity.
  double gravity_potential = 0.0;
  // Free-surface liquids only:
  double surface_seconds = 0.0;   ///< level set advection, redistancing, volume restoration, cut tets
  double liquid_volume = 0.0;     ///< sum_t |Omega_t| after the step [m^3]
  double volume_drift = 0.0;      ///< (V_tracked - V_target) / V_target before the restoration [-]
  // Particles only (FluidParams::particles):
  double particle_seconds = 0.0;  ///< particle motion, location, reseeding, P2G and G2P
  int num_particles = 0;          ///< after the step
  int particles_added = 0;        ///< by reseeding in the step
  int particles_removed = 0;      ///< by reseeding (crowded tets) and outside the liquid
};

class FluidSolver {
 public:
  explicit FluidSolver(FluidParams params);

  /// Sets the current mesh and per-fluid-tet fields (zero fields if `fields` is empty).
  /// @throws std::invalid_argument if the field sizes do not match the fluid tets
  void initialize(const mesh::TetMesh& mesh, FluidFields fields = {});

  /// Advances by h [s] onto `mesh` (may differ from the previous mesh): advection, sources, body
  /// forces, projection. A viscous fluid then takes its implicit viscous step on the projected
  /// velocity and a second projection (the pressure is the sum of both): a liquid at rest under
  /// gravity is at rest after the first projection (hydrostatic pressure), so the no-slip walls
  /// never hold its weight, and the viscous step sees the flow the body forces start (before it
  /// saw only the advected velocity, zero in a first step, so a liquid of 1e9 Pa s fell as an
  /// inviscid one does in its first step and crept at about g h per step after).
  /// @throws std::runtime_error on NaN/Inf, SolverError if the pressure solve fails.
  StepReport step(const mesh::TetMesh& mesh, const BoundaryConditions& bc, double h);

  /// Makes the fluid a liquid with a free surface: `level_set` (one value per fluid node of the
  /// current mesh; liquid where < 0) is redistanced, and its liquid volume becomes the volume the
  /// run keeps (LiquidOptions::restore_volume). From then on every step advects the level set,
  /// projects with p = 0 on the surface (free_surface_projection.hpp) and extends the velocity into
  /// the air. @throws std::invalid_argument on a size mismatch, band <= 0 or no liquid at all
  void set_liquid(Eigen::VectorXd level_set, LiquidOptions options);
  bool has_free_surface() const { return free_surface_; }
  /// Nodal level set on the current mesh [m] (empty without a free surface).
  const Eigen::VectorXd& level_set() const { return level_set_; }
  /// Liquid part of every tet of the current mesh (free surface only).
  const LiquidGeometry& liquid() const { return liquid_; }
  /// The liquid volume the run keeps [m^3].
  double target_liquid_volume() const { return target_volume_; }

  /// Projects the current velocity only (no advection, no forces): initial conditions, potential flow.
  StepReport project_only(const BoundaryConditions& bc, double h);

  // ---- pieces for the simultaneous coupling (coupling/coupled_stepper.hpp) ----
  /// Steps 1-3 of step(): advects onto `mesh`, classifies `bc`, applies sources and body forces,
  /// leaving the intermediate velocity v* in fields().velocity (no projection).
  /// When `mesh` is the current mesh moved (the same tets and labels), the fluid is a gas and the
  /// advection is not BFECC, predict() moves the fluid mesh in place (advect_onto_moved): one
  /// fluid mesh in memory instead of the old and the new one.
  StepReport predict(const mesh::TetMesh& mesh, const BoundaryConditions& bc, double h);
  /// The solver's state before a step onto `mesh`, for undoing the step (CoupledStepper's step
  /// halving): a copy of the solver that, when predict() will move the mesh in place, holds the
  /// mesh's node positions instead of sharing the mesh.
  struct UndoPoint;
  UndoPoint undo_point(const mesh::TetMesh& mesh) const;
  /// Back to `point`, taken before this solver's last predict() (and nothing since but the other
  /// steps of a coupled step): the fluid mesh moved in place gets the point's geometry back,
  /// recomputed from its node positions.
  void undo(UndoPoint point);
  /// Eq. (8), interior part: v = v* - (h/rho) G p with the pressure p [Pa] per fluid node that the
  /// coupled solve found (a free surface: v = v* - (h/rho) B p on the liquid and the extension
  /// into the air, free_surface_projection.hpp); then the finiteness check and the statistics of `rep`.
  /// @throws std::runtime_error on NaN/Inf
  StepReport apply_pressure(Eigen::VectorXd pressure, double h, StepReport rep);

  const FluidParams& params() const { return params_; }
  /// True if some tet has a viscosity > 0 (FluidParams::viscosity, viscosity_regions).
  bool viscous() const;
  const FluidMesh& mesh() const { return *mesh_; }
  const FluidFields& fields() const { return *fields_; }
  /// The fields to write (a copy first if an undo point still shares them).
  FluidFields& fields() { return writable_fields(); }
  /// Gᵀ V v per node of the current mesh (p1_operators.hpp, gradient_transpose_volume) for the
  /// velocity v carried onto it by the last predict(), before its body forces and sources [m³/s]:
  /// the divergence of the coupled step's start-of-step fluid state (coupling/coupled_stepper.cpp).
  /// Kept only after keep_advected_divergence(true) (empty otherwise): one value per node instead
  /// of the advected velocity's three per tet.
  const Eigen::VectorXd& advected_divergence() const { return advected_divergence_; }
  /// Whether predict() keeps advected_divergence() (the simultaneous coupling's mean constraint).
  void keep_advected_divergence(bool keep) { keep_advected_divergence_ = keep; }
  const Eigen::VectorXd& pressure() const { return pressure_; }
  const ClassifiedBoundary& boundary() const { return boundary_; }

  /// Pressure force on solid `subdomain` [N]: sum over its interface faces of int p n dA, with n the
  /// fluid's outward normal (pointing into the solid) and p linear on each face (exact quadrature).
  Eigen::Vector3d pressure_force(int subdomain) const;
  /// Viscous force on solid `subdomain` [N] in the last step: the sum over its no-slip interface
  /// nodes of -(K U^{n+1})_i (implicit_viscosity.hpp), the reaction that kept those nodes at the
  /// solid's velocity; 0 for an inviscid fluid or slip solids.
  Eigen::Vector3d viscous_force(int subdomain) const;
  /// The last viscous step's force on every fluid node held at a solid's velocity [N] (0 elsewhere).
  const std::vector<Eigen::Vector3d>& viscous_node_force() const { return viscous_force_; }
  /// Its 3x3 derivative block per fluid node, -d(force)/d(node velocity) (ViscosityReport::wall_stiffness).
  const std::vector<Eigen::Matrix3d>& viscous_node_stiffness() const { return viscous_stiffness_; }

  /// The particles carrying the velocity (FluidParams::particles; null before the first step).
  const ParticleSet* particles() const { return particles_.get(); }

  /// Fills rep's energies for the current state: kinetic_energy and gravity_potential [J].
  void report_energies(StepReport& rep) const;

  /// Checkpoints (apps/run/checkpoint.hpp; fluid_solver_state.cpp): everything a step changes —
  /// the mesh and its topology record, the fields, the advected divergence (if kept), the
  /// pressure, the classified boundary, the level set with its cut-tet geometry and the volume kept.
  /// The parameters and liquid options are the set-up's: restore into a solver set up from the
  /// same scene. read_state throws BinaryReadError on a truncated or corrupt state.
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);

  /// The tets and labels of the TetMesh the current fluid mesh was built from.
  struct SourceTopology {
    std::vector<std::array<int, 4>> tets;
    std::vector<int> subdomain;
  };

 private:
  void apply_sources(const BoundaryConditions& bc, double h);
  /// The implicit viscous step (implicit_viscosity.hpp) on fields_.velocity with the Dirichlet
  /// nodes of `bc` (viscous_boundary.hpp); fills rep's viscosity columns and viscous_force_.
  void apply_viscosity_step(const BoundaryConditions& bc, double h, StepReport& rep);
  /// Steps 2-3 of level_set.hpp on the current mesh, then the cut-tet geometry; fills rep's
  /// liquid columns. `phi` is the advected level set.
  void update_liquid(Eigen::VectorXd phi, StepReport& rep);
  /// The liquid's velocity on the tets that hold at least min_kept_fraction of liquid, extended
  /// over the others.
  void extend_liquid_velocity();
  /// Per tet: 1 where the velocity is the fluid's own (all tets; a liquid: those holding at least
  /// min_kept_fraction of liquid), 0 where it is extended.
  std::vector<char> kept_tets() const;
  // ---- particles (fluid_solver_particles.cpp; particles/particles.hpp) ----
  /// The first seeding, on the current mesh and velocity, if there are no particles yet.
  void seed_particles();
  /// The particles of the step, moved through the current (old) mesh's velocity over h.
  std::shared_ptr<ParticleSet> advected_particles(const std::vector<double>* weight, const PointLocator& old_locator,
                                                  double h);
  /// Steps 1-3 of particles.hpp on the new mesh (after set_mesh and the liquid's update): find,
  /// keep in the liquid, reseed, P2G into fields_->velocity.
  void transfer_to_mesh(std::shared_ptr<ParticleSet> moved, const std::vector<int>& old_to_new, StepReport& rep);
  /// Step 5 of particles.hpp (G2P) after the pressure, if this step carried particles to the mesh.
  void transfer_to_particles(StepReport& rep);
  StepReport finish(const BoundaryConditions& bc, double h, StepReport rep);
  /// The projection of finish(): with p = 0 on a free surface when the liquid has air nodes.
  ProjectionReport project_velocity(double h);
  /// True if `mesh` has the tets and labels mesh_ was built from (moved, not remeshed), so that
  /// its fluid mesh is mesh_ with new geometry (update_fluid_mesh_geometry).
  bool built_from(const mesh::TetMesh& mesh) const;
  /// built_from(mesh), and neither a free surface nor BFECC, which read the new mesh while advecting.
  bool moves_in_place(const mesh::TetMesh& mesh) const;
  /// *fields_, copied first if a copy of the solver shares it.
  FluidFields& writable_fields();
  /// predict()'s steps after the advection: the classified boundary, sources, viscosity, body forces.
  StepReport add_forces(const BoundaryConditions& bc, double h, StepReport rep);
  /// mesh_ = fluid_mesh (the old mesh_ becomes the spare), remembering the topology of `mesh`
  /// unless it is the same as before.
  void set_mesh(const mesh::TetMesh& mesh, std::shared_ptr<FluidMesh> fluid_mesh, bool same_topology);
  /// The storage for this step's moved mesh: the spare if no copy of the solver holds it, else a
  /// new mesh; holding mesh_'s topology (copied into it unless the spare has it already).
  std::shared_ptr<FluidMesh> moved_mesh_storage();
  /// The members write_state / read_state write and read, in order (fluid_solver_state.cpp).
  template <class Archive>
  void state(Archive& a);

  /// The mesh before mesh_, kept to be overwritten by the next moved mesh (its arrays have their
  /// sizes already: a step allocates, and page-faults, no mesh). A copy of the solver starts
  /// without one, so that no two solvers write into one mesh.
  struct SpareMesh {
    std::shared_ptr<FluidMesh> mesh;
    bool same_topology = false;  // mesh has mesh_'s tets, nodes and faces (only its geometry is old)
    SpareMesh() = default;
    SpareMesh(const SpareMesh&) {}
    SpareMesh& operator=(const SpareMesh&) { return *this = SpareMesh(); }
    SpareMesh(SpareMesh&&) = default;
    SpareMesh& operator=(SpareMesh&&) = default;
  };

  FluidParams params_;
  // The fluid mesh, shared with the copies of the solver, so that copying the solver copies no
  // mesh. A step moves it in place only when no copy holds it (moves_in_place; an UndoPoint holds
  // node positions instead); otherwise it builds the moved mesh in spare_ (or a new one) and swaps.
  std::shared_ptr<FluidMesh> mesh_ = std::make_shared<FluidMesh>();
  SpareMesh spare_;
  // Shared with the copies of the solver, as mesh_ is (replaced, never written, on a new topology).
  std::shared_ptr<const SourceTopology> source_ = std::make_shared<const SourceTopology>();
  // Shared with the copies of the solver (an undo point) until one writes them (writable_fields):
  // a step replaces them by the advected fields before it writes, so an undo point copies none.
  std::shared_ptr<FluidFields> fields_ = std::make_shared<FluidFields>();
  Eigen::VectorXd advected_divergence_;  // see advected_divergence()
  bool keep_advected_divergence_ = false;
  Eigen::VectorXd pressure_;
  ClassifiedBoundary boundary_;
  bool initialized_ = false;
  bool viscosity_after_projection_ = false;  ///< step(): add_forces leaves the viscous step out
  bool free_surface_ = false;
  LiquidOptions liquid_options_;
  Eigen::VectorXd level_set_;
  LiquidGeometry liquid_;
  double target_volume_ = 0.0;
  std::vector<Eigen::Vector3d> viscous_force_;      // per fluid node, see viscous_node_force()
  std::vector<Eigen::Matrix3d> viscous_stiffness_;  // per fluid node, see viscous_node_stiffness()
  // The viscous step's fit rings (viscosity/node_fit.hpp) of mesh_, kept while its topology holds.
  std::vector<std::vector<int>> viscous_rings_;
  // The particles (shared with the copies of the solver until a step replaces or writes them).
  std::shared_ptr<ParticleSet> particles_;
  // v^{P2G} of this step (FLIP's G2P reads v^{n+1} - v^{P2G}); cleared by the G2P.
  TetVectors transferred_velocity_;
  bool particles_on_mesh_ = false;  // this step's P2G done and its G2P not yet
};

struct FluidSolver::UndoPoint {
  FluidSolver solver;                  ///< the solver; without its mesh when `nodes` is not empty
  std::vector<Eigen::Vector3d> nodes;  ///< the fluid mesh's node positions [m]; empty: `solver` shares the mesh
};

}  // namespace tetfsi::fluid
