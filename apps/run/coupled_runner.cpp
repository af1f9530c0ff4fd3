/// @file coupled_runner.cpp
/// Fluid (smoke or liquid) and deformable tet solids advanced together: one linear system for the
/// fluid pressure and the solid velocities per step (Chentanez et al. 2006, eq. 7), or the
/// time-splitting baseline (coupling/coupled_stepper.hpp). Runs scenes whose fluid is not `none`
/// and whose solids are all tet solids (model `tet_fem`), at least one deforming (motion `none`)
/// and the others kinematic (their nodes follow their /motion, prescribed each step); the optional
/// `coupling` block chooses scheme, solver and mesh update.
///
/// The shared mesh is one CGAL complex of the domain box with every solid inside; each solid's FEM
/// mesh is its subdomain. A `sphere_shell` solid's cavity is fluid too (mesh::build_complex with
/// cavities); with `fluid.fill: cavities` the mesh is the shell and its liquid alone, no box
/// (mesh::mesh_filled_shell): the fluid is a closed region bounded only by the shell. Each step the
/// fluid vertices follow the solids and the fluid is remeshed around them when needed
/// (coupling/mesh_update.hpp); a motion too large for one step (a tet inverts even with the fluid
/// following) is retried in halves (simulation.max_step_halvings), and stops the run with a clear
/// error, exit code 1, when even the shortest step fails. The container's walls are contact planes
/// for the solids (coupling.wall_contact), set back by a fluid film (coupling.contact_gap).
///
/// Watchdog (watchdog.hpp): inverted solid tets; and, when every load is conservative (a closed
/// container with walls only: no inflow, open face or emitter, no vorticity confinement;
/// coupled_energy_source), the total energy E = fluid kinetic 1/2 rho sum V_t |v_t|^2 + fluid
/// gravity potential -rho g . int x dV + solid kinetic, strain, spring and gravity potential
/// (CoupledStepReport::total_energy) may only fall (the semi-Lagrangian advection and the
/// chentanez Newmark scheme dissipate), so a rise above E_0 by more than max_energy_growth x the
/// scale (the largest fluid kinetic + solid kinetic + strain + spring energy so far, at least
/// sum m_s |g| L_s over the solids, plus rho V |g| h for a free-surface liquid of volume V on
/// cells of edge h) is energy from nowhere: e.g. the added-mass instability of
/// time splitting with a solid lighter than the fluid it moves. The work that inflows, open faces
/// and emitters supply is not accounted: those scenes are not watched (run.log says why).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "apps/run/scene_values.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/fluid_probe.hpp"
#include "apps/run/watchdog.hpp"
#include "apps/run/container.hpp"
#include "apps/run/coupled_energy.hpp"
#include "apps/run/fluid_columns.hpp"
#include "apps/run/fluid_setup.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_geometry.hpp"
#include "apps/run/solid_params.hpp"
#include "apps/run/solid_springs.hpp"
#include "apps/run/surface_refinement.hpp"
#include "support/stopwatch.hpp"
#include "apps/run/tet_tools.hpp"
#include "coupling/coupled_stepper.hpp"
#include "fluid/io/fluid_output.hpp"
#include "fluid/stable_step.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/quality.hpp"
#include "solid/integrator/spd_solver.hpp"

namespace tetfsi::run {
namespace {


class CoupledRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy& time_steps, spdlog::logger& log) override {
    solid::limit_blas_threads(1);  // multi-threaded OpenBLAS slows CHOLMOD here (solid/README.md)
    const auto& js = scene.json;
    const auto& m = js.at("mesh");
    mesh::MeshSizing sizing = mesh_sizing(m);
    watchdog_ = watchdog_settings(js.at("simulation"));
    // A free surface with surface_edge_length: finer near the liquid (surface_refinement.hpp).
    refinement_ = surface_refinement(js);
    if (refinement_.on())
      sizing.size_at = refinement_.field(liquid_region_distance(js));
    sizing_ = sizing;

    std::vector<mesh::SurfaceMesh> surfaces, cavities;
    std::vector<solid::TetMaterial> materials;
    std::vector<solid::TetModelOptions> model_options;
    for (const auto& s : js.at("solids")) {
      names_.push_back(s.at("name").get<std::string>());
      std::vector<std::string> warnings;
      cavities.emplace_back();  // stays empty unless a sphere_shell
      surfaces.push_back(surface_of(s, warnings, &cavities.back()));
      for (const auto& w : warnings) log.warn("{}", w);
      materials.push_back(tet_material(s.at("material")));
      model_options.push_back(tet_model_options(s.at("material")));
    }
    mesh::TetMesh complex;
    const bool cavity_only = js.at("fluid").value("fill", "domain") == "cavities";
    try {
      // fill "cavities": the shell and its liquid alone, no box (schema: exactly one shell).
      complex = cavity_only ? mesh::mesh_filled_shell(surfaces[0], cavities[0], sizing)
                            : mesh_container(js["domain"], surfaces, sizing, cavities);
    } catch (const mesh::MeshError& e) {
      throw meshing_failure(e, names_);
    }
    const mesh::QualityReport quality = mesh::quality_report(complex);
    log.info("mesh quality: {}", quality.summary());
    if (quality.degenerate + quality.inverted > 0)
      throw InputError(fmt::format("the mesh has {} flat and {} inverted tets; with thin solids (sheets) kept sharp "
                                   "this happens: set mesh.feature_angle_deg to 0 (round the edges) or make "
                                   "mesh.edge_length_near_solids smaller than the thickness",
                                   quality.degenerate, quality.inverted));

    const auto& c = js.at("coupling");
    coupling::CoupledSettings cs;
    edge_near_ = coupling::fluid_edge_length_near_solids(complex);
    cs.scheme = c.at("scheme") == "time_splitting" ? coupling::CouplingScheme::kTimeSplitting
                                                    : coupling::CouplingScheme::kSimultaneous;
    scheme_ = c.at("scheme").get<std::string>();
    cs.solver = coupling::parse_coupled_solver_kind(c.at("solver").get<std::string>());
    cs.solver_options.tolerance = c.at("tolerance").get<double>();
    cs.solver_options.max_iterations = c.at("max_iterations").get<int>();
    cs.solver_options.reuse_factorization = c.at("reuse_factorization").get<bool>();
    // A run that writes no checkpoints frees what only a checkpoint needs (schur_cg's Ŝ).
    cs.solver_options.keep_checkpoint_state = js.at("export").value("checkpoint_every", 0) > 0;
    cs.compare_solvers = c.at("compare_solvers").get<std::vector<std::string>>();
    compare_solvers_ = cs.compare_solvers;
    cs.newmark = c.at("newmark") == "trapezoidal" ? solid::NewmarkScheme::kTrapezoidal
                                                  : solid::NewmarkScheme::kChentanez;
    cs.solid_gravity = vec3(js.at("simulation").at("gravity"));
    cs.mean_constraint = c.at("constraint") == "step_mean";
    cs.keep_closed_volumes = c.at("keep_closed_volumes").get<bool>();
    cs.max_step_halvings = time_steps.max_step_halvings;
    cs.mesh_update.policy = coupling::parse_mesh_update_policy(c.at("mesh_update").get<std::string>());
    cs.mesh_update.remesh_below_deg = c.at("remesh_below_deg").get<double>();
    cs.mesh_update.motion_solver = coupling::parse_motion_solver(c.at("mesh_motion_solver").get<std::string>());
    // 0: CoupledStepper's default band, four near-solid cells (never the whole fluid).
    cs.mesh_update.remesh.band = js.at("fluid").at("remesh_band").get<double>();
    try {
      stepper_ = std::make_unique<coupling::CoupledStepper>(complex, fluid_params(js, log), materials, cs, model_options);
    } catch (const std::exception& e) {
      throw InputError(std::string("cannot set up the coupled model: ") + e.what());
    }
    try {
      set_initial_liquid(js, stepper_->fluid(), log);
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("/fluid/regions: ") + e.what());
    }
    if (refinement_.on()) {
      refinement_.mark(stepper_->fluid());
      log.info("{}", refinement_.summary());
    }

    // The container's walls (a filled shell has none: its fluid is inside the solid).
    ContainerWalls walls;
    const double gap = c.at("contact_gap").get<double>() > 0 ? c.at("contact_gap").get<double>() : 0.5 * edge_near_;
    if (c.at("wall_contact").get<bool>() && !cavity_only && js.contains("domain")) {
      walls = container_walls(js.at("domain"), gap);
      log.info("wall contact: {} wall(s), fluid film {:.3g} m", walls.count(), gap);
    }
    const auto& solids = js.at("solids");
    for (int i = 0; i < stepper_->num_solids(); ++i) {
      auto& integrator = stepper_->solid(i);
      for (std::size_t r = 0; r < solids[i].at("fixed_regions").size(); ++r) {
        const auto& box = solids[i]["fixed_regions"][r];
        const auto nodes = integrator.nodes_in_box(vec3(box.at("lo")), vec3(box.at("hi")));
        if (nodes.empty())  // as the solid runner: a box that holds nothing is refused, not ignored
          throw InputError(fmt::format("/solids/{}/fixed_regions/{}: the box contains no node of solid '{}'", i, r,
                                       names_[i]));
        integrator.fix_components(nodes, fixed_components(box), vec3(box.at("velocity")));
      }
      add_scene_springs(integrator, solids[i], i, names_[i], log);
      integrator.set_uniform_velocity(vec3(solids[i].at("initial_velocity")));
      if (js.contains("obstacles")) {
        const auto& o = js["obstacles"];
        for (const auto& p : o.at("planes")) integrator.obstacles().add_plane({vec3(p.at("point")), vec3(p.at("normal"))});
        for (const auto& b : o.at("boxes")) integrator.obstacles().add_box({vec3(b.at("lo")), vec3(b.at("hi"))});
        integrator.obstacles().set_friction(o.at("friction").get<double>());
      }
      walls.add_to(integrator.obstacles());
      // A kinematic solid (a /motion other than none) is a tet solid whose every node is
      // prescribed: before each step its nodes get the velocity (x(t + h) − xⁿ)/h that lands them
      // where the motion puts them at t + h (eq. 5 with u^{n+1} = uⁿ = that velocity), so the fluid
      // sees its motion through H's fixed columns and it deforms nothing.
      if (solids[i].at("motion").at("type") != "none") {
        std::vector<int> all(stepper_->solid_model(i).num_nodes());
        std::iota(all.begin(), all.end(), 0);
        integrator.fix_nodes(all);
        kinematic_.push_back({i, solids[i].at("motion")});
      }
    }
    solid::SurfaceContactSettings surface;
    surface.gap = gap;
    surface.between_solids = c.at("solid_contact").get<bool>();
    surface.friction = js.contains("obstacles") ? js["obstacles"].at("friction").get<double>() : 0.0;
    std::vector<char> self_contact;
    for (int i = 0; i < stepper_->num_solids(); ++i) self_contact.push_back(solids[i].at("self_contact").get<bool>());
    stepper_->enable_surface_contact(surface, self_contact);
    const int selfs = static_cast<int>(std::count(self_contact.begin(), self_contact.end(), 1));
    if (selfs > 0 || (surface.between_solids && stepper_->num_solids() > 1))
      log.info("surface contact: {} solid(s) between each other, {} with itself, fluid film {:.3g} m, friction {}",
               surface.between_solids ? stepper_->num_solids() : 0, selfs, gap, surface.friction);
    if (!kinematic_.empty()) {
      stepper_->set_before_step([this](double t, double h) { prescribe_kinematic(t, h); });
      log.info("coupled model: {} kinematic solid(s) move as prescribed, the others deform", kinematic_.size());
    }
    const double ambient = js.at("fluid").value("ambient_temperature", 293.15);
    if (js.contains("domain")) stepper_->fluid_boundary().patches = boundary_patches(js, ambient);
    emitters_ = timed_sources(js, log);
    setup_energy_watch(js, log);
    log.info("coupled model: {} solid(s), {} fluid tets, scheme {}, solver {} (pressure solver: {}), {}, mesh update {} (motion: {})",
             stepper_->num_solids(), stepper_->fluid().mesh().num_tets(), c.at("scheme").get<std::string>(),
             c.at("solver").get<std::string>(), fluid::to_string(stepper_->fluid().params().solver.backend),
             time_steps.dt ? fmt::format("dt = {} s", *time_steps.dt)
                           : fmt::format("CFL {} on edge {:.3g} m, at most {:.4g} s", time_steps.cfl, edge_near_,
                                         time_steps.frame_interval()),
             c.at("mesh_update").get<std::string>(), c.at("mesh_motion_solver").get<std::string>());
    log_ = &log;
  }

  std::vector<std::string> phases() const override {
    std::vector<std::string> p = {"remesh", "advect", "solid_assemble", "interface", "solve"};
    add_fluid_phases(stepper_->fluid(), p);
    return p;
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c = {"fluid_tets",    "remeshed",          "min_dihedral", "pressure_unknowns", "solid_dofs",
                                  "solver_iterations", "solver_residual", "solver_factor_age",
                                  "fluid_kinetic", "solid_kinetic",     "solid_strain", "gravity_potential",
                                  "fluid_gravity_potential", "total_energy", "contacts", "contact_rounds", "substeps",
                                  "closed_volume_error", "closed_volume_correction"};
    if (stepper_->has_obstacles()) c.push_back("wall_clearance");
    add_fluid_columns(stepper_->fluid(), c);
    for (const std::string& name : compare_solvers_)
      c.insert(c.end(), {"compare_" + name + "_seconds", "compare_" + name + "_iterations"});
    return c;
  }
  /// The scene's `dt`, or the CFL step (fluid/stable_step.hpp) on the fluid edge length next to
  /// the solids, with the solids' speed and without the free-fall bound, at most one frame.
  double max_dt(const scene::TimeStepPolicy& time_steps) const override {
    if (time_steps.dt) return *time_steps.dt;
    return fluid::cfl_step(stepper_->fluid(), time_steps.cfl, edge_near_, stepper_->max_solid_speed(),
                           time_steps.frame_interval(), false);
  }

  StepReport step(double h) override {
    auto& sources = stepper_->fluid_boundary().sources;
    sources.clear();
    for (const auto& e : emitters_)
      if (e.active(stepper_->time())) sources.push_back(e.source);
    if (refinement_.on()) set_size_field();
    coupling::CoupledStepReport r;
    // Where the energy is watched, a step that would gain more than a twentieth of its scale is
    // taken in halves first (CoupledStepper::set_energy_guard); the watchdog judges the rest.
    if (energy_source_.empty()) stepper_->set_energy_guard(energy_.last(), kEnergyGuard * energy_.scale());
    try {
      r = stepper_->step(h);
    } catch (const mesh::MeshError& e) {
      throw RunError(fmt::format("coupled step at t = {:.6g} s ({} coupling): {}", stepper_->time(), scheme_, e.what()));
    } catch (const std::exception& e) {
      // Any other failed coupled step is a failed run (exit code 1), not an internal error: the
      // state diverged (e.g. the added-mass instability of time splitting, a fluid tet inverted by
      // a runaway solid). Nothing of it is written.
      throw RunError(fmt::format("coupled step at t = {:.6g} s ({} coupling): {}", stepper_->time(), scheme_,
                                 e.what()));
    }
    if (r.mesh_update.remesh_rejected && rejected_remeshes_++ == 0)
      log_->warn("t = {} s: remeshing did not improve the moved fluid mesh (min dihedral {:.3g} deg), so the moved "
                 "mesh was kept (later cases: `remeshed` = 0 in stats.csv with a low min_dihedral)",
                 r.time, r.mesh_update.min_dihedral_deg);
    if (r.mesh_update.remeshed)
      log_->debug("t = {} s: fluid remeshed, {} tets, min dihedral {:.3g} deg, {:.3g} s", r.time, r.fluid.num_tets,
                  r.mesh_update.min_dihedral_deg, r.mesh_update.seconds);
    if (refinement_.on()) {
      if (r.mesh_update.size_field_fitted) refinement_.mark(stepper_->fluid());
      surface_left_refined_zone_ = refinement_.left_zone(stepper_->fluid().level_set());
    }
    last_ = r;
    energy_.record(r.total_energy(), r.fluid_kinetic + r.solid_kinetic + r.solid_strain + r.spring_energy);
    StepReport out;
    out.dt = h;
    out.phase_seconds = {r.mesh_update.seconds, r.fluid.advect_seconds + r.fluid.forces_seconds,
                         r.solid_assemble_seconds,
                         // the fluid mesh's geometry and boundary classification belong to the
                         // assembly of eq. (7) as much as J, H and C do
                         r.interface_seconds + r.fluid.assemble_seconds,
                         r.solve.setup_seconds + r.solve.solve_seconds};
    out.values = {double(r.fluid.num_tets), double(r.mesh_update.remeshed), r.mesh_update.min_dihedral_deg,
                  double(r.pressure_unknowns), double(r.solid_dofs),
                  double(r.solve.iterations), r.solve.residual.max(), double(r.solve.factor_age), r.fluid_kinetic, r.solid_kinetic,
                  r.solid_strain, r.solid_gravity_potential, r.fluid_gravity_potential, r.total_energy(),
                  double(r.solve.contacts), double(r.solve.contact_rounds), double(r.substeps),
                  r.closed_volume_error, r.closed_volume.correction};
    if (stepper_->has_obstacles()) out.values.push_back(r.obstacle_clearance);
    add_fluid_values(stepper_->fluid(), r.fluid, out.phase_seconds, out.values);
    for (const coupling::ComparedSolve& c : r.compared) {  // -1 iterations: it missed its tolerance
      if (!c.failure.empty()) log_->warn("t = {} s: compare_solvers: {}", r.time, c.failure);
      out.values.insert(out.values.end(), {c.seconds, c.failure.empty() ? double(c.iterations) : -1.0});
    }
    return out;
  }

  std::string unphysical() const override {
    // Energy first: a coupling instability that has begun to invert the solid is named as such.
    if (energy_source_.empty() && energy_.exceeded(watchdog_)) return coupled_energy_diagnosis(*stepper_, energy_, names_, scheme_, watchdog_);
    for (int i = 0; i < stepper_->num_solids(); ++i) {
      auto what = inverted_tets(stepper_->solid_model(i), stepper_->solid(i).displacement(), names_[i], i, watchdog_);
      if (!what.empty()) return what;
    }
    return "";
  }

  std::string non_finite() const override {
    for (int i = 0; i < stepper_->num_solids(); ++i)
      if (!stepper_->solid(i).displacement().allFinite()) return fmt::format("solid '{}' displacement", names_[i]);
    const auto& u = stepper_->fluid().fields().velocity;
    for (std::size_t t = 0; t < u.size(); ++t)
      if (!u[t].allFinite()) return fmt::format("fluid velocity of tet {}", t);
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    write_fluid_frame(out, frame, time, stepper_->fluid(), stepper_->fluid_node_positions());
    for (int i = 0; i < stepper_->num_solids(); ++i) {
      const auto& integrator = stepper_->solid(i);
      mesh::TetMesh deformed = stepper_->solid_mesh(i).mesh;
      const Eigen::VectorXd x = integrator.positions();
      std::vector<double> d, v;
      std::vector<Eigen::Vector3d> velocity(deformed.vertices.size());
      for (int a = 0; a < deformed.num_vertices(); ++a) {
        deformed.vertices[a] = x.segment<3>(3 * a);
        velocity[a] = integrator.velocity().segment<3>(3 * a);
        for (int k = 0; k < 3; ++k) {
          d.push_back(integrator.displacement()[3 * a + k]);
          v.push_back(velocity[a][k]);
        }
      }
      auto grid = mesh::io::make_grid(deformed);
      grid.add_point_data("displacement", 3, d);
      grid.add_point_data("velocity", 3, v);
      out.write_grid(names_[i], frame, time, grid);
      std::vector<int> to_tet_vertex;
      const auto surface = boundary_surface(deformed, &to_tet_vertex);
      std::vector<Eigen::Vector3d> surface_velocity;
      for (int a : to_tet_vertex) surface_velocity.push_back(velocity[a]);
      out.write_surface(names_[i], frame, surface, surface_velocity);
    }
  }

  /// The coupled model's state (CoupledStepper::write_state), the energy watchdog's baselines and
  /// the last step's energies (the total_energy and fluid_kinetic_energy probes).
  void write_checkpoint(BinaryWriter& out) const override {
    stepper_->write_state(out);
    const_cast<EnergyWatch&>(energy_).state(out);
    out(rejected_remeshes_, last_.fluid_kinetic, last_.fluid_gravity_potential, last_.solid_kinetic, last_.solid_strain,
        last_.spring_energy, last_.solid_gravity_potential);
  }
  void read_checkpoint(BinaryReader& in) override {
    stepper_->read_state(in);
    energy_.state(in);
    in(rejected_remeshes_, last_.fluid_kinetic, last_.fluid_gravity_potential, last_.solid_kinetic, last_.solid_strain,
       last_.spring_energy, last_.solid_gravity_potential);
  }

  std::vector<double> probe(const scene::Json& p) const override {
    const std::string kind = p.at("kind").get<std::string>();
    if (kind == "total_energy") return {last_.total_energy()};
    if (kind == "fluid_volume")
      return {stepper_->fluid().has_free_surface() ? stepper_->fluid().liquid().total_volume() : stepper_->fluid_volume()};
    if (kind == "fluid_kinetic_energy") return {last_.fluid_kinetic};
    if (kind == "fluid_point") return {fluid_point_value(stepper_->fluid(), p)};
    if (!p.contains("solid")) return {};
    const int i = solid_index(p.at("solid").get<std::string>());
    if (i < 0) return {};
    const auto& model = stepper_->solid_model(i);
    const Eigen::VectorXd x = stepper_->solid(i).positions();
    if (kind == "fluid_force") {
      const std::string part = p.value("part", "total");
      Eigen::Vector3d f = Eigen::Vector3d::Zero();
      if (part != "viscous") f += stepper_->pressure_force(i);
      if (part != "pressure") f += stepper_->viscous_force(i);
      return {f.x(), f.y(), f.z()};
    }
    if (kind == "contact_force") {
      const Eigen::Vector3d f = stepper_->contact_force(i);
      return {f.x(), f.y(), f.z()};
    }
    if (kind == "solid_volume") {
      double volume = 0;
      for (const auto& t : model.tets())
        volume += mesh::signed_volume(x.segment<3>(3 * t[0]), x.segment<3>(3 * t[1]), x.segment<3>(3 * t[2]),
                                      x.segment<3>(3 * t[3]));
      return {volume};
    }
    if (kind == "point_displacement") {
      const int best = nearest_node(model.reference_positions(), vec3(p.at("point")));
      const Eigen::Vector3d u = stepper_->solid(i).displacement().segment<3>(3 * best);
      return {u.x(), u.y(), u.z()};
    }
    return {};
  }

 private:
  /// The liquid surface's sizing field for the next step's mesh update; when the surface left its
  /// refined zone, a refit where the field moved since the last fit, with the first mesh's
  /// grading toward the solids in CGAL's field (the refit may reach them; SizeFieldRequest).
  void set_size_field() {
    coupling::SizeFieldRequest request;
    request.size_at = refinement_.current_field(stepper_->fluid());
    if (surface_left_refined_zone_) {
      request.size_now = request.size_at;
      request.size_then = refinement_.fitted_field();
      request.far_edge = refinement_.far_edge();
      request.ratio = SurfaceRefinement::kResize;
      request.rings = SurfaceRefinement::kRings;
      if (auto solid = solid_graded_field(stepper_->mesh(), sizing_))
        request.size_at = [surface = request.size_now, solid = std::move(solid)](const Eigen::Vector3d& x) {
          return std::min(surface(x), solid(x));
        };
    }
    stepper_->set_size_field(std::move(request));
  }


  /// Starts the energy balance at the initial state, or logs why the scene is not watched.
  void setup_energy_watch(const scene::Json& js, spdlog::logger& log) {
    energy_source_ = coupled_energy_source(js);
    if (!energy_source_.empty()) {
      log.info("watchdog: the energy balance is not watched: {}", energy_source_);
      return;
    }
    energy_ = coupled_energy_watch(*stepper_, js);
    log.info("watchdog: energy balance of the closed container, E_0 = {:.6g} J, scale {:.3g} J",
             energy_.start(), energy_.scale());
  }

  int solid_index(const std::string& name) const {
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == name) return static_cast<int>(i);
    return -1;
  }

  /// The velocities of the kinematic solids' nodes over [t, t + h]: (x(t + h) − xⁿ)/h, x(t) the
  /// motion of the node's rest position (moved(), scene_values.hpp).
  void prescribe_kinematic(double t, double h) {
    for (const auto& k : kinematic_) {
      auto& integrator = stepper_->solid(k.solid);
      const Eigen::VectorXd& X = stepper_->solid_model(k.solid).reference_positions();
      const Eigen::VectorXd x = integrator.positions();
      for (int a = 0; a < static_cast<int>(X.size() / 3); ++a) {
        const Eigen::Vector3d target = moved(k.motion, X.segment<3>(3 * a), t + h);
        integrator.set_prescribed_velocity(a, (target - x.segment<3>(3 * a)) / h);
      }
    }
  }

  struct Kinematic {
    int solid;
    scene::Json motion;
  };
  std::vector<Kinematic> kinematic_;
  std::unique_ptr<coupling::CoupledStepper> stepper_;
  WatchdogSettings watchdog_;
  EnergyWatch energy_;          ///< energy balance (only if energy_source_ is empty)
  std::string energy_source_;   ///< why the energy is not watched, or ""
  /// A step gaining more than this fraction of the energy scale is halved (set_energy_guard).
  static constexpr double kEnergyGuard = 0.05;
  std::vector<std::string> names_;
  coupling::CoupledStepReport last_;
  std::vector<TimedSource> emitters_;
  double edge_near_ = 0;  ///< fluid edge length next to the solids at set-up [m]: the CFL cell, the default film
  spdlog::logger* log_ = nullptr;
  int rejected_remeshes_ = 0;
  mesh::MeshSizing sizing_;                  ///< of the first mesh (its grading toward the solids)
  SurfaceRefinement refinement_;             ///< the mesh finer at the liquid surface (off without one)
  bool surface_left_refined_zone_ = false;   ///< refit the mesh to the surface in the next step
  std::string scheme_;
  std::vector<std::string> compare_solvers_;  ///< coupling.compare_solvers: stats.csv columns
};

}  // namespace

std::unique_ptr<Simulation> make_coupled_runner() { return std::make_unique<CoupledRunner>(); }

}  // namespace tetfsi::run
