#pragma once
/// @file coupled_stepper.hpp
/// The coupled time step of Chentanez et al. 2006 (sec. 3) for a fluid and deformable tet solids
/// that share one TetMesh (fluid = subdomain 1, solid i = subdomain 2 + i). step(h) runs, in order
/// (the mesh conforms to the solids at Xⁿ + dⁿ when it starts):
///
///  1. Fluid predictor: advect and add body forces, v* (fluid::FluidSolver::predict).
///  2. assemble_solid_rows: each solid's integrator forms A and b of eq. (4) at dⁿ.
///  3. assemble_interface: H over the triangles fluid and solid share, J = Hᵀ (sec. 3.4,
///     interface_maps.hpp).
///  4. assemble_fluid_rows: (h/ρ) L and r of eq. (6) on the pressure unknowns.
///  5. solve: eq. (7) for u^{n+1} and p^{n+1} together (coupled_solver.hpp), by default with the
///     paper's end-of-step constraint (CoupledSettings::mean_constraint).
///  6. update: fluid velocity by eq. (8), solid displacement by eq. (5).
///  7. Mesh (for the next step): the solid vertices of the shared mesh move to X + d^{n+1}, the
///     fluid vertices follow, and the fluid is remeshed around the solids as
///     CoupledSettings::mesh_update says (mesh_update.hpp); the solid tets keep their
///     connectivity, so solid state carries over. If the motion inverts or flattens a tet, the
///     step is undone and halved (CoupledSettings::max_step_halvings). The fluid solver keeps the
///     mesh of step 1 (at xⁿ); fluid_node_positions() gives its nodes moved with the solids to
///     x^{n+1}, the positions output draws the fluid's t^{n+1} fields on.
///
/// Step 5 includes the solids' contact with their obstacles (the container's walls, planes,
/// boxes): the active set of NewmarkIntegrator::step with its penalty rows in A, so the fluid and
/// the contact forces are found together (solve_with_contact); and, once enable_surface_contact is
/// called, the contact of the solids with each other and with themselves (solid/contact/surface_contact.hpp),
/// whose rows couple the solids' blocks of A.
///
/// A liquid with a free surface (fluid::FluidSolver::set_liquid) takes part as itself: its pressure
/// unknowns are the liquid nodes (p = 0 in the air), its rows the cut-tet system of
/// fluid/liquid/free_surface_projection.hpp with the same H over the interface triangles; H's rows
/// of air nodes drop out, so the solid feels the liquid's pressure only, and the dry side of a
/// triangle that the surface crosses carries the linear fall of p to zero at its air vertices (a
/// first-order waterline). CoupledSettings::mean_constraint does not apply to it.
///
/// The time-splitting baseline (CouplingScheme::kTimeSplitting) replaces 5 by two solves: the
/// solid with the previous step's pressure, A u^{n+1} = b + J pⁿ, then the fluid with the new solid
/// velocity as its boundary flux, (h/ρ) L p^{n+1} = r − H u^{n+1}. It is kept to show where it fails
/// (the added-mass instability of Causin, Gerbeau & Nobile 2005) and the simultaneous system does not.
#include <Eigen/Core>
#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "coupling/closed_regions.hpp"
#include "coupling/mesh_update.hpp"
#include "coupling/solver_comparison.hpp"
#include "coupling/solvers/coupled_solver.hpp"
#include "fluid/fluid_solver.hpp"
#include "mesh/submesh.hpp"
#include "mesh/tet_mesh.hpp"
#include "solid/contact/surface_contact.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/tet/material.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::coupling {

enum class CouplingScheme { kSimultaneous, kTimeSplitting };

/// The coupled model's settings. The step length is not one of them: the caller gives each step(h)
/// its own.
struct CoupledSettings {
  CouplingScheme scheme = CouplingScheme::kSimultaneous;
  CoupledSolverKind solver = CoupledSolverKind::SchurCG;
  CoupledSolverOptions solver_options;
  Eigen::Vector3d solid_gravity = Eigen::Vector3d::Zero();  ///< gravity on the solids [m/s²]
  /// Solid time integration: the paper's eq. (18) as printed (θ = 1, dissipative) or the
  /// energy-conserving trapezoidal rule (θ = ½); see solid/integrator/newmark.hpp.
  solid::NewmarkScheme newmark = solid::NewmarkScheme::kChentanez;
  /// Simultaneous scheme: impose the incompressibility constraint on the step's mean state,
  /// Gᵀ V (vⁿ + v^{n+1})/2 = H (uⁿ + u^{n+1})/2 with H at the predicted mid-step interface
  /// xⁿ + (h/2) uⁿ, instead of the paper's end-of-step form (eq. 7). Both Newmark schemes move the
  /// solid by (h/2)(uⁿ + u^{n+1}), so only this form keeps a closed cavity's volume to O(h³) per
  /// step: on data/scenes/filled_toy.json (0.3 s, h = 1/400 s) the cavity lost 1.9e-3 of its volume
  /// with the end-of-step form and 7.9e-7 with this one (each half alone: 9.5e-4). When the
  /// start-of-step state already satisfies the constraint on the current mesh, the two coincide.
  /// Off by default: the start-of-step defect it carries to the right-hand side flips sign every
  /// step, and on the open-jet bar (data/scenes/bar_compare.json, h = 1/30 s) the bar's swing
  /// grew with alternating sign until the run stopped at 0.77 s; eq. (7) stays bounded there.
  bool mean_constraint = false;
  /// Simultaneous scheme: keep the volume of every closed fluid region (no open face, no free
  /// surface, no inflow) whose boundary moves with the solids, by the start-velocity projection and
  /// the volume source of closed_regions.hpp. Off: the region drifts by O(h²) per step and by more
  /// where contact changes the solids' velocity (the paper's eq. 7 alone).
  bool keep_closed_volumes = true;
  /// How the fluid mesh follows the solids (move only, remesh when needed, remesh every step).
  MeshUpdateOptions mesh_update;
  /// A step whose solid motion would invert or flatten fluid tets (even with the fluid vertices
  /// following) is undone and taken as two steps of h/2, each of which may be halved again, at
  /// most this many times (so down to h / 2^max_step_halvings). 0: such a step throws at once.
  int max_step_halvings = 0;
  /// Called at the start of every step taken (each half of a halved step too) with its start time
  /// and length [s]: a caller prescribes the velocities of kinematic solids over [t, t + h] here
  /// (NewmarkIntegrator::fix_nodes), so that their nodes land where their motion puts them.
  std::function<void(double t, double h)> before_step;
  /// Benchmark: after each step's solve, solve the same system again with these and record their
  /// times (`bicgstab`, `umfpack`, `projection`; solver_comparison.hpp). Empty: none.
  std::vector<std::string> compare_solvers;
};

/// One stats.csv row of a coupled step.
struct CoupledStepReport {
  int step = 0;
  double time = 0;                  ///< t^{n+1} [s]
  fluid::StepReport fluid;          ///< advect / forces timings, counts
  CoupledSolveReport solve;         ///< which solver ran, iterations, residuals, time
  std::vector<ComparedSolve> compared;  ///< CoupledSettings::compare_solvers, in that order
  MeshUpdateReport mesh_update;     ///< remeshed or only moved, min dihedral angle, time
  double solid_assemble_seconds = 0;
  double interface_seconds = 0;     ///< H and the reduced fluid blocks
  int pressure_unknowns = 0, solid_dofs = 0, interface_triangles = 0;
  double fluid_kinetic = 0;         ///< ½ ρ Σ V_t |v_t|² [J]
  double fluid_gravity_potential = 0;  ///< −ρ g · ∫ x dV over the fluid (liquid part) at t^{n+1} [J]
  double solid_kinetic = 0, solid_strain = 0, spring_energy = 0, solid_gravity_potential = 0;  ///< [J]
  ClosedVolumeReport closed_volume; ///< the closed regions' corrections (closed_regions.hpp)
  double closed_volume_error = 0;   ///< (V − V₀)/V₀ of the closed region furthest off, at t^{n+1}
  /// The smallest signed distance of a solid node to its obstacles (the container's walls set back
  /// by the film, planes, boxes) at t^{n+1} [m]; negative: a node inside; +infinity: none.
  double obstacle_clearance = std::numeric_limits<double>::infinity();
  int substeps = 1;                 ///< steps actually taken (more when the step was halved)
  double min_substep = 0;           ///< the shortest of them [s]
  double total_energy() const {
    return fluid_kinetic + fluid_gravity_potential + solid_kinetic + solid_strain + spring_energy +
           solid_gravity_potential;
  }
};

class CoupledStepper {
 public:
  /// @param mesh       the shared complex (fluid subdomain 1, solid i subdomain 2+i), at rest
  /// @param fluid      fluid parameters (density, gravity, advection, ...)
  /// @param materials  one material per solid, in subdomain order
  /// @param model_options  element options per solid (empty: the defaults for all)
  /// @throws std::invalid_argument if a solid subdomain is missing or model_options has another size,
  ///         solid::SolidError on bad materials
  CoupledStepper(mesh::TetMesh mesh, fluid::FluidParams fluid, const std::vector<solid::TetMaterial>& materials,
                 CoupledSettings settings, const std::vector<solid::TetModelOptions>& model_options = {});

  int num_solids() const { return static_cast<int>(solids_.size()); }
  /// The i-th solid's integrator: set fixed nodes, springs, initial velocity, obstacles here.
  solid::NewmarkIntegrator& solid(int i) { return *solids_[i].integrator; }
  const solid::TetModel& solid_model(int i) const { return *solids_[i].model; }
  /// Solid node -> shared-mesh vertex map of solid i.
  const mesh::Submesh& solid_mesh(int i) const { return solids_[i].submesh; }
  fluid::FluidSolver& fluid() { return fluid_; }
  /// Contact between the solids' surfaces (and of solid i with itself if self_contact[i]; empty:
  /// none), inside eq. (7) with the obstacle contact (solid/contact/surface_contact.hpp).
  /// @throws std::invalid_argument on bad settings
  void enable_surface_contact(const solid::SurfaceContactSettings& settings, const std::vector<char>& self_contact = {});
  /// A sizing field for the next step's mesh update (e.g. finer at a liquid's free surface).
  void set_size_field(SizeFieldRequest request);
  /// See CoupledSettings::before_step.
  void set_before_step(std::function<void(double t, double h)> f) { settings_.before_step = std::move(f); }
  /// Energy guard of step halving: a step (or part of a halved one) whose total energy
  /// (CoupledStepReport::total_energy) ends more than `max_gain` [J] above that of the state it
  /// started from is undone and taken in halves, as a step whose motion spoils the mesh is (within
  /// max_step_halvings; the last halving keeps its result). For scenes whose loads are all
  /// conservative, where a rise is energy from nowhere: the rotation of a stiff body that turns by
  /// ω h per step along eq. (5)'s straight lines stretches it by (ω h)²/2 (a ball of 10 kg/m³ and
  /// E = 1e8 Pa hitting a lid through water at h = 1/30 s gained 5 J in a step); each halving cuts
  /// that fourfold. `energy` [J] is the total energy of the current state; max_gain ≤ 0: off.
  void set_energy_guard(double energy, double max_gain) {
    energy_guard_energy_ = energy;
    energy_guard_gain_ = max_gain;
  }
  const fluid::FluidSolver& fluid() const { return fluid_; }
  /// Positions [m] of the fluid solver's nodes (fluid().mesh().nodes order) at time(), t^{n+1}.
  /// fluid().mesh() is the mesh the last step ran on, whose vertices are at the solids' positions
  /// of the step's start, xⁿ; the step ends by moving that mesh so that its solid vertices sit at
  /// x^{n+1} (MeshUpdateResult::moved_vertices, before any remeshing), and these are its fluid
  /// nodes there. A frame drawn with them has every fluid interface vertex on the solid vertex
  /// it shares, at the same time; the fields (fluid().fields(), pressure, level set) are the
  /// t^{n+1} values, unchanged. Before the first step: fluid().mesh().nodes.
  std::vector<Eigen::Vector3d> fluid_node_positions() const;
  /// The fluid's pressure force on solid i in the last step [N]: the sum over its nodes of
  /// J p^{n+1} (J = Hᵀ, f_a = ∫_Γ φ_a p n dA, coupled_system.hpp), n into the solid. Zero before the first step.
  Eigen::Vector3d pressure_force(int i) const {
    return i < static_cast<int>(pressure_force_.size()) ? pressure_force_[i] : Eigen::Vector3d::Zero();
  }
  /// The viscous force of the fluid on solid i in the last step [N] (0 for an inviscid fluid): the
  /// sum over its no-slip interface nodes of the reaction -(K U^{n+1})_i of the viscous step
  /// (fluid/viscosity/implicit_viscosity.hpp) at the solid's velocity uⁿ.
  Eigen::Vector3d viscous_force(int i) const {
    return i < static_cast<int>(viscous_force_.size()) ? viscous_force_[i] : Eigen::Vector3d::Zero();
  }
  /// The contact force on solid i in the last step [N]: its obstacle contacts' (the container's
  /// walls, planes, boxes) and its pairs with other solids' normal constraint forces, f n each.
  Eigen::Vector3d contact_force(int i) const;
  /// Walls, open patches, inflows and sources of the fluid (solid interfaces are handled here).
  fluid::BoundaryConditions& fluid_boundary() { return boundary_; }
  const mesh::TetMesh& mesh() const { return mesh_; }
  double time() const { return time_; }
  /// Volume of the fluid [m³] with the solid vertices at their current positions Xⁿ + dⁿ: the sum
  /// of the fluid tets' signed volumes. Only the fluid's boundary vertices matter, so for a fluid
  /// that is a closed cavity of a solid (mesh::mesh_filled_shell) this is the cavity's volume.
  double fluid_volume() const;

  /// One coupled step of length h [s] (e.g. shortened to land on a frame time), halved as
  /// CoupledSettings::max_step_halvings allows when its solid motion would spoil the fluid mesh.
  /// The mesh follows the solids at the end of the step, so that a failed motion is caught while
  /// the step can still be undone.
  /// @throws CoupledSolveError, fluid::SolverError, solid::SolidError or std::runtime_error on
  ///         divergence (never returns a non-finite state); std::invalid_argument if h <= 0
  CoupledStepReport step(double h);
  /// The largest speed of a solid node now, max_a |u_a| over every solid [m/s] (0 without
  /// solids): the solid speed of the CFL step (fluid/stable_step.hpp).
  double max_solid_speed() const {
    double u_max = 0;
    for (const Solid& s : solids_) {
      const Eigen::VectorXd& u = s.integrator->velocity();
      for (Eigen::Index a = 0; a < u.size() / 3; ++a) u_max = std::max(u_max, u.segment<3>(3 * a).norm());
    }
    return u_max;
  }

  /// Checkpoints (coupled_stepper_state.cpp): everything the steps change — the shared mesh, the
  /// solid-node maps, the fluid solver, the solids' integrators, the coupled solver's lagged
  /// blocks, the mesh motion cached since the last remesh, the previous pressure, contact state,
  /// time and step — bit for bit, so that the steps after read_state are those the saved run
  /// would have taken. Read into a stepper set up from the same scene (materials, settings,
  /// springs, obstacles, boundary patches are the set-up's). @throws BinaryReadError
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);

 private:
  struct Solid {
    mesh::Submesh submesh;
    std::unique_ptr<solid::TetModel> model;
    std::unique_ptr<solid::NewmarkIntegrator> integrator;
    int dof_offset = 0;
  };
  struct SolidRows;  // A, b of eq. (4) over all solids
  struct Interface;  // the pressure unknowns and H of sec. 3.4
  struct FluidRows;  // (h/ρ) L and r of eq. (6)
  /// Everything a step changes except the mesh, which changes only once the step has succeeded.
  struct Snapshot {
    fluid::FluidSolver::UndoPoint fluid;
    std::vector<solid::NewmarkIntegrator::State> solids;
    std::vector<double> previous_vertex_pressure;
    std::vector<int> surface_contact_nodes;
    std::vector<double> surface_contact_forces;
    double time = 0;
    int step = 0;
  };
  Snapshot snapshot() const;
  void restore(Snapshot snapshot);
  /// step(h) with `halvings` halvings left.
  CoupledStepReport step_or_halve(double h, int halvings);
  /// One step of length h without retry: the numbered list of the file comment, then the mesh
  /// update. With `guard_energy`, throws EnergyGainError before the mesh update when the step's
  /// end state has more energy than set_energy_guard allows (the step can still be undone).
  CoupledStepReport step_once(double h, bool guard_energy = false);
  /// Thrown by step_once for a step that gained energy beyond set_energy_guard's bound.
  struct EnergyGainError : std::runtime_error {
    using std::runtime_error::runtime_error;
  };
  SolidRows assemble_solid_rows(double h, CoupledStepReport& report);
  Interface assemble_interface(double h, const SolidRows& solid, CoupledStepReport& report) const;
  FluidRows assemble_fluid_rows(double h, const Interface& interface);
  /// Eq. (7), or the two solves of time splitting; u, p are the new solid velocities and pressures.
  /// @throws std::runtime_error if the solution is not finite
  CoupledSolveReport solve(const CoupledSystem& sys, const std::vector<int>& unknown, Eigen::VectorXd& u,
                           Eigen::VectorXd& p);
  /// solve() with the solids' contact with their obstacles (solid/integrator/newmark.hpp): the
  /// active set of the solid-only step, its penalty rows κ n nᵀ added to A in the simultaneous
  /// system, so the fluid responds to the contact within the step; the system is solved again
  /// while the active set changes (at most kMaxContactRounds more solves). Modifies sys.A, sys.b.
  CoupledSolveReport solve_with_contact(double h, CoupledSystem& sys, const std::vector<int>& unknown,
                                        Eigen::VectorXd& u, Eigen::VectorXd& p);
public:
  /// Whether some solid has obstacles (the container's walls, planes, boxes) to touch.
  bool has_obstacles() const;

 private:
  bool has_surface_contact() const { return surface_contact_ && surface_contact_->enabled(); }
  /// Per solid dof: its velocity is prescribed (fixed, driven or kinematic nodes).
  std::vector<char> prescribed_dofs() const;
  /// Fluid node -> pressure unknown, −1 where the pressure is prescribed (open nodes and, for a
  /// liquid with a free surface, the air nodes); `count` gets the number of unknowns.
  std::vector<int> pressure_unknowns(int& count) const;
  /// TetMesh vertex -> system solid node id (dof / 3), −1 for fluid-only vertices.
  std::vector<int> solid_node_of_vertex() const;
  /// Closed regions (closed_regions.hpp): finds them on the step's mesh and projects the solids'
  /// start velocity uⁿ onto the velocities that keep their volumes.
  void begin_closed_volumes(double h, const std::vector<int>& unknown, CoupledStepReport& report);
  /// Correction 3 of closed_regions.hpp: where the solution (u, p) of sys leaves a closed region's
  /// volume at the step's end off V₀ by more than closed_volume_tolerance, adds the multiples of
  /// the responses to the regions' unit dilatations that put it back. sys is left as it was.
  void restore_closed_volumes(double h, CoupledSystem& sys, const std::vector<int>& unknown, Eigen::VectorXd& u,
                              Eigen::VectorXd& p, CoupledStepReport& report);
  /// 1e-4 of the smaller of closed region c's reference volume and the volume of the solids on its
  /// boundary [m³].
  double closed_volume_tolerance(int c) const;
  /// −ρ g · ∫ x dV over the fluid at t^{n+1}, after the step's mesh update: for a fluid that fills
  /// its region, from the mesh that conforms to the solids at t^{n+1} (the fluid solver's own
  /// figure in report.fluid is on the mesh of tⁿ, one step behind the solids, which showed as
  /// energy from nowhere when a sinking ball stopped on the floor); for a liquid with a free
  /// surface, report.fluid's.
  double fluid_gravity_potential(const CoupledStepReport& report) const;
  /// Volume [m³] and first moment ∫ x dV [m⁴] of the fluid tets of mesh_ with vertices at x.
  std::pair<double, Eigen::Vector3d> fluid_moments(const std::vector<Eigen::Vector3d>& x) const;
  static constexpr int kMaxContactRounds = 8;
  /// The viscous traction of a viscous fluid on the solids' rows, linearized about uⁿ: the fluid's
  /// viscous step held the solid interface nodes at uⁿ and found the reaction F(uⁿ) with its
  /// diagonal 3x3 blocks C (FluidSolver::viscous_node_stiffness); the impulse over the step is taken
  /// as h F(uⁿ) - h C (u^{n+1} - uⁿ), so A += C (symmetric positive semi-definite: eq. 7 stays
  /// symmetric) and b += F(uⁿ) + C uⁿ (eq. 18's rows are forces: A = M/h + ...). The drag is thus implicit in the solid's own velocity
  /// (a light solid in a viscous fluid does not overshoot), lagged in the fluid's (the fluid's
  /// velocity near the solid is the viscous step's, before the pressure). C is K_ii, the fluid
  /// around the node held: it over-estimates the drag's derivative for large h, which damps but
  /// does not change a steady state (there u^{n+1} = uⁿ).
  void add_viscous_drag(SolidRows& rows);
  /// Eqs. (8) and (5): the fluid takes the pressure p, the solids the velocity u.
  void update(double h, const Eigen::VectorXd& u, const Eigen::VectorXd& p, const std::vector<int>& unknown,
              CoupledStepReport& report);
  /// The solids' node positions at the step's end for u^{n+1} = u (all solids, dof order): eq. (5)
  /// (NewmarkIntegrator::end_displacement).
  Eigen::VectorXd end_solid_positions(double h, const Eigen::VectorXd& u) const;
  /// The solids' node positions Xⁿ + dⁿ and velocities uⁿ, all solids in dof order (3 per node).
  Eigen::VectorXd solid_positions() const;
  Eigen::VectorXd solid_velocities() const;
  /// The shared mesh's vertices with each solid node moved to its entry of solid_x (dof order).
  std::vector<Eigen::Vector3d> mesh_vertices_at(const Eigen::VectorXd& solid_x) const;
  /// The previous step's pressure on the m pressure unknowns (fluid node -> unknown map).
  Eigen::VectorXd previous_pressure(const std::vector<int>& unknown, int m) const;
  /// The simultaneous scheme with CoupledSettings::mean_constraint.
  bool mean_constraint() const;
  /// A liquid with a free surface that has air this step: its pressure unknowns are the liquid
  /// nodes and its rows the cut-tet system (fluid/liquid/free_surface_projection.hpp).
  bool free_surface() const;
  /// Step 7, last in step(): moves (and maybe remeshes) mesh_ to the solids' positions X + d^{n+1}
  /// for the next step; remaps the solid-node and pressure maps through the new vertex numbering.
  MeshUpdateReport update_mesh_to_solids();

  mesh::TetMesh mesh_;
  CoupledSettings settings_;
  fluid::FluidSolver fluid_;
  fluid::BoundaryConditions boundary_;
  std::vector<Solid> solids_;
  int num_solid_dofs_ = 0;                        // 3 x the nodes of all solids
  std::unique_ptr<CoupledSolver> solver_;
  std::unique_ptr<SolverComparison> comparison_;  ///< null unless settings_.compare_solvers
  std::vector<double> previous_vertex_pressure_;  // per mesh vertex, for time splitting
  double min_dihedral_deg_ = 0;                   // of the fluid tets of mesh_
  std::unique_ptr<MeshUpdater> mesh_updater_;     // caches the mesh motion operator between remeshes
  std::unique_ptr<solid::SurfaceContact> surface_contact_;  // solid-solid and self contact, or none
  ClosedVolumes closed_volumes_;                  // reference volumes of the closed fluid regions
  double energy_guard_energy_ = 0, energy_guard_gain_ = 0;  // set_energy_guard
  std::vector<Eigen::Vector3d> pressure_force_;  // per solid, of the last step [N]
  std::vector<Eigen::Vector3d> viscous_force_;   // per solid, of the last step [N]
  // The vertices of the mesh fluid_ last stepped on, moved to the solids at t^{n+1}
  // (MeshUpdateResult::moved_vertices); empty before the first step.
  std::vector<Eigen::Vector3d> fluid_mesh_moved_vertices_;
  // The last step's (h/ρ) L, handed back after its solve: the next step's assembly sums its values
  // into this pattern when the mesh only moved (mesh/column_gather.hpp; bit for bit the same).
  SparseMatrix fluid_rows_pattern_;
  double time_ = 0;
  int step_ = 0;
};

}  // namespace tetfsi::coupling
