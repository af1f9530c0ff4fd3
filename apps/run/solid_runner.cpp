/// @file solid_runner.cpp
/// Solid-only scenes with tetrahedral FEM bodies (Chentanez et al. 2006 sec. 3.2, appendix
/// eqs. 9-18): /fluid/type is "none" and at least one solid deforms (motion "none", model
/// "tet_fem"; hex8 solids go to the hex runner). Each deforming solid is meshed alone
/// (mesh::mesh_solid, no fluid) or, with geometry "volume_mesh", takes the tets of its file
/// (volume_mesh_of), and becomes a TetModel advanced by its own NewmarkIntegrator
/// with the scene's gravity, fixed regions (per component), initial velocity, static obstacles and,
/// with /solids/*/self_contact, contact of its surface with itself. Solids do not collide with each other. Solids with a prescribed motion in the same scene are not moved
/// (a warning says so).
///
/// Loads (/solids/i/boundary_conditions, solid/loads/region_conditions.hpp): dead nodal forces,
/// tractions, moment tractions and body forces go to the integrator as constant external forces,
/// `fixed` conditions hold their components, a follower `pressure` is folded into the model
/// (solid::FollowerLoadedModel). `model.analysis: "static"`: load stepping with Newton-Raphson
/// (solid/analysis/static_solver.hpp) in setup(), as for hex8 solids (static_steps.hpp): frame k and
/// probes.csv row k are load step k, time = load factor.
///
/// stats.csv columns (sums over the solids): kinetic 1/2 u^T M u [J], strain [J], gravity
/// potential -sum m g.x [J], total [J], solver iterations, inverted elements, contact nodes, and
/// the potential of the dead loads V_f = -f.d [J] (the watched energy includes it), and the steps
/// taken (a step that inverts a tet is retried in halves, /simulation/max_step_halvings). Static runs:
/// load steps, Newton iterations, most iterations in a step, step cuts.
#include <fmt/format.h>

#include <array>
#include <map>

#include "apps/run/scene_values.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_geometry.hpp"
#include "apps/run/solid_params.hpp"
#include "apps/run/solid_springs.hpp"
#include "apps/run/static_steps.hpp"
#include "support/stopwatch.hpp"
#include "apps/run/tet_tools.hpp"
#include "apps/run/watchdog.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/quality.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/loads/follower_pressure.hpp"
#include "solid/output/solid_output.hpp"
#include "solid/solid_error.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::run {
namespace {


struct Body {
  std::string name;
  std::unique_ptr<solid::TetModel> model;
  std::unique_ptr<solid::NewmarkIntegrator> integrator;
  mesh::SurfaceMesh surface;      ///< boundary of the tet mesh, at rest
  std::vector<int> surface_nodes; ///< tet-mesh node of each surface vertex
  int index = 0;                  ///< /solids/index
  std::string scheme;             ///< /solids/index/integrator/scheme
  EnergyWatch energy;             ///< energy balance (watchdog.hpp)
  bool driven = false;            ///< a fixed region moves at a prescribed velocity (does work)
  solid::BoundaryConditions bc;   ///< /solids/index/boundary_conditions (+ fixed_regions if static)
  std::unique_ptr<solid::FollowerLoadedModel> loaded;  ///< dynamic with a follower pressure
  StaticSteps steps;              ///< static analysis: the load steps
};

/// Potential of the dead loads, V_f = -f.d [J] (their work is f.d).
double load_potential(const Body& b) {
  return b.bc.forces.size() > 0 ? -b.bc.forces.dot(b.integrator->displacement()) : 0.0;
}

/// The tet mesh as the boundary conditions see it.
solid::LoadedMesh loaded_mesh(const mesh::TetMesh& tets, const solid::TetModel& model) {
  solid::LoadedMesh m;
  m.vertices = tets.vertices;
  m.boundary = solid::tet_boundary_faces(tets.tets);
  m.masses = model.lumped_masses();
  m.density = model.material().density;
  return m;
}

/// Holds the `fixed` dofs of bc (per node, its components) in the integrator.
void fix_dofs(solid::NewmarkIntegrator& integ, const std::vector<int>& dofs) {
  std::map<int, std::array<bool, 3>> held;
  for (int dof : dofs) {
    auto [it, added] = held.try_emplace(dof / 3, std::array<bool, 3>{false, false, false});
    it->second[dof % 3] = true;
  }
  for (const auto& [node, comps] : held) integ.fix_components({node}, comps);
}

/// Kinetic + strain + spring energy of a state [J] (the part that is not gravitational).
double mechanical(const solid::StepStats& e) { return e.kinetic + e.strain + e.spring; }

class SolidRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy& time_steps, spdlog::logger& log) override {
    solid::limit_blas_threads(1);  // solid/README.md: a busy-waiting BLAS costs more than it gains here
    const auto& js = scene.json;
    const auto& sim = js.at("simulation");
    const auto& m = js.at("mesh");
    const mesh::MeshSizing sizing = mesh_sizing(m);
    const auto& obs = js.at("obstacles");

    for (std::size_t i = 0; i < js.at("solids").size(); ++i) {
      const auto& s = js["solids"][i];
      const std::string ptr = fmt::format("/solids/{}", i);
      if (!deforms_as(s, "tet_fem")) {
        log.warn("solid '{}' ({}) is not simulated by the solid runner and is left out",
                 s.at("name").get<std::string>(), s.at("motion").at("type") != "none" ? "kinematic" : "hex8");
        continue;
      }
      Body b;
      b.name = s.at("name").get<std::string>();
      std::vector<std::string> warnings;
      mesh::TetMesh tets;
      if (s.at("geometry").at("type") == "volume_mesh") {  // the file's tets as they are
        tets = volume_mesh_of(s, warnings);
      } else {
        const mesh::SurfaceMesh surface = surface_of(s, warnings);
        try {
          tets = mesh::mesh_solid(surface, sizing, mesh::solid_subdomain(static_cast<int>(i)));
        } catch (const mesh::MeshError& e) {
          throw InputError(fmt::format("{}: meshing solid '{}' failed: {}", ptr, b.name, e.what()));
        }
      }
      for (const auto& w : warnings) log.warn("{}", w);
      log.info("mesh: solid '{}': {} vertices, {} tets; {}", b.name, tets.num_vertices(), tets.num_tets(),
               mesh::quality_report(tets).summary());

      const auto& mat = s.at("material");
      const solid::TetMaterial material = tet_material(mat);
      try {
        material.validate();
      } catch (const solid::SolidError& e) {
        throw InputError(fmt::format("{}/material: {}", ptr, e.what()));
      }
      static_ = is_static(s);
      try {
        const solid::NewmarkSettings settings = newmark_settings(s, js);
        b.model = std::make_unique<solid::TetModel>(tets, material, tet_model_options(mat));
        b.bc = solid::make_conditions(region_conditions(s, static_), loaded_mesh(tets, *b.model));
        const solid::ElasticModel* model = b.model.get();
        if (!static_ && !b.bc.pressures.empty()) {  // follower pressure folded into the model's force
          b.loaded = std::make_unique<solid::FollowerLoadedModel>(*b.model, b.bc.pressures);
          model = b.loaded.get();
        }
        b.integrator = std::make_unique<solid::NewmarkIntegrator>(*model, settings);
      } catch (const solid::SolidError& e) {  // e.g. a degenerate tet from the mesher: try another mesh size
        throw InputError(fmt::format("{}: solid '{}' (mesh.edge_length {} m): {}", ptr, b.name,
                                     sizing.edge_length, e.what()));
      } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("{}/boundary_conditions: solid '{}': {}", ptr, b.name, e.what()));
      }
      b.surface = boundary_surface(tets, &b.surface_nodes);
      b.index = static_cast<int>(i);
      if (static_) {
        b.steps = solve_in_steps(b.name, *b.model, b.bc, static_options(s), log);
        bodies_.push_back(std::move(b));
        continue;
      }
      auto& integ = *b.integrator;
      fix_dofs(integ, b.bc.fixed_dofs);
      if (b.bc.forces.size() > 0) integ.set_external_forces(b.bc.forces);
      if (b.loaded) log.info("solid '{}': a follower pressure does work on it; its energy is not watched", b.name);
      for (std::size_t r = 0; r < s.at("fixed_regions").size(); ++r) {
        const auto& box = s["fixed_regions"][r];
        const auto nodes = integ.nodes_in_box(vec3(box.at("lo")), vec3(box.at("hi")));
        if (nodes.empty())
          throw InputError(fmt::format("{}/fixed_regions/{}: the box contains no node of solid '{}'", ptr, r, b.name));
        integ.fix_components(nodes, fixed_components(box), vec3(box.at("velocity")));
        if (vec3(box.at("velocity")).squaredNorm() > 0) {
          b.driven = true;
          log.info("solid '{}': fixed region {} is driven at {} m/s; its energy is not watched (the drive does "
                   "work on it)", b.name, r, box.at("velocity").dump());
        }
        log.info("solid '{}': fixed region {} holds {} nodes", b.name, r, nodes.size());
      }
      add_scene_springs(integ, s, static_cast<int>(i), b.name, log);
      integ.set_uniform_velocity(vec3(s.at("initial_velocity")));
      for (const auto& p : obs.at("planes"))
        integ.obstacles().add_plane({vec3(p.at("point")), vec3(p.at("normal"))});
      for (const auto& bx : obs.at("boxes")) integ.obstacles().add_box({vec3(bx.at("lo")), vec3(bx.at("hi"))});
      integ.obstacles().set_friction(obs.at("friction").get<double>());
      if (s.at("self_contact").get<bool>()) {
        // No fluid keeps the surfaces apart here: a film of 5% of a surface edge keeps the edges
        // between the contact nodes from crossing.
        const double gap = 0.05 * mean_edge_length(b.surface);
        integ.enable_self_contact(b.model->tets(), gap, obs.at("friction").get<double>());
        log.info("solid '{}': self-contact on, film {:.3g} m", b.name, gap);
      }
      b.scheme = s.at("integrator").at("scheme").get<std::string>();
      {
        const auto e = integ.energies();
        const double weight = b.model->lumped_masses().sum() * vec3(js.at("simulation").at("gravity")).norm();
        b.energy = EnergyWatch(e.total() + load_potential(b), mechanical(e),
                               energy_floor(b.model->reference_positions(), weight));
      }
      log.info("solid '{}': scheme {}, solver {}, constitutive {}", b.name,
               s["integrator"]["scheme"].get<std::string>(), s["integrator"]["linear_solver"].get<std::string>(),
               mat["constitutive"].get<std::string>());
      bodies_.push_back(std::move(b));
    }
    log.info("solid runner: {} tet solid(s), step {} s", bodies_.size(), time_steps.fixed_step());
    watchdog_ = watchdog_settings(sim);
    max_step_halvings_ = time_steps.max_step_halvings;
  }

  bool time_dependent() const override { return !static_; }
  std::vector<std::string> phases() const override { return {"assemble", "solve"}; }
  std::vector<std::string> columns() const override {
    if (static_) return {"load_steps", "newton_iterations", "max_iterations_per_step", "step_cuts"};
    return {"kinetic", "strain", "gravity_potential", "total_energy", "solver_iterations", "inverted", "contacts",
            "load_potential", "substeps"};
  }
  double max_dt(const scene::TimeStepPolicy& time_steps) const override { return time_steps.fixed_step(); }
  std::vector<double> load_factors() const override {
    return static_ && !bodies_.empty() ? bodies_.front().steps.load_factors : std::vector<double>{};
  }
  void select_load_step(int k) override { selected_ = load_factors().at(k); }
  StepReport setup_report() const override {
    StepReport r;
    std::vector<const StaticSteps*> steps;
    double assemble = 0, solve = 0;
    for (const auto& b : bodies_) {
      steps.push_back(&b.steps);
      assemble += b.steps.assembly_seconds;
      solve += b.steps.solve_seconds;
    }
    r.phase_seconds = {assemble, solve};
    r.values = static_totals(steps);
    return r;
  }

  StepReport step(double h) override {
    StepReport r;
    r.dt = h;
    double assemble = 0, solve = 0;
    std::vector<double> v(9, 0.0);
    for (auto& b : bodies_) {
      Substeps taken;
      try {
        step_or_halve(b, h, max_step_halvings_, taken);  // the driver may shorten a step to land on a frame
      } catch (const solid::SolidError& e) {
        const bool stvk = b.model->material().law == solid::ConstitutiveLaw::kStVK;
        throw RunError(fmt::format("solid '{}': {}{}", b.name, e.what(),
                                   stvk ? " (in the scene: material.constitutive \"neohookean\")" : ""));
      }
      const solid::StepStats& st = b.integrator->last_stats();
      const double loads = load_potential(b);
      b.energy.record(st.total() + loads, mechanical(st));
      assemble += taken.assembly_seconds;
      solve += taken.solve_seconds;
      const double vals[] = {st.kinetic, st.strain, st.gravity_potential, st.total(), double(taken.solver_iterations),
                             double(st.inverted), double(st.contacts), loads, double(taken.count)};
      for (int k = 0; k < 9; ++k) v[k] += vals[k];
    }
    r.phase_seconds = {assemble, solve};
    r.values = v;
    return r;
  }

  std::string non_finite() const override {
    for (const auto& b : bodies_) {
      const auto& d = displacement(b);
      const auto& u = b.integrator->velocity();
      for (int i = 0; i < d.size(); ++i) {
        if (!std::isfinite(d[i])) return fmt::format("solid '{}': displacement of node {}", b.name, i / 3);
        if (!std::isfinite(u[i])) return fmt::format("solid '{}': velocity of node {}", b.name, i / 3);
      }
    }
    return "";
  }

  std::string unphysical() const override {
    if (static_) return "";
    for (const auto& b : bodies_) {
      auto what = inverted_tets(*b.model, b.integrator->displacement(), b.name, b.index, watchdog_);
      // A driven region (fixed_regions[].velocity) does work on the body: its energy may rise.
      if (what.empty() && !b.driven && !b.loaded) what = b.energy.check(b.name, b.index, b.scheme, watchdog_);
      if (!what.empty()) return what;
    }
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    for (const auto& b : bodies_) {
      if (!static_) {
        write(out, b, frame, time, b.integrator->displacement(), b.integrator->velocity());
        continue;
      }
      write_load_steps(out, b.name, b.steps);  // every load step, "time" = load factor
      const auto& st = b.steps;
      for (std::size_t k = 0; k < st.states.size(); ++k)
        write(out, b, static_cast<int>(k), st.load_factors[k], st.states[k], Eigen::VectorXd::Zero(st.states[k].size()));
    }
  }

  void write(Output& out, const Body& b, int frame, double time, const Eigen::VectorXd& d,
             const Eigen::VectorXd& u) const {
    try {
      out.write_grid(b.name, frame, time, solid::solid_grid(*b.model, d, u));
    } catch (const solid::SolidError& e) {
      throw RunError(fmt::format("solid '{}': {}", b.name, e.what()));
    }
    mesh::SurfaceMesh now = b.surface;
    std::vector<Eigen::Vector3d> vel(now.vertices.size());
    for (std::size_t k = 0; k < now.vertices.size(); ++k) {
      const int n = b.surface_nodes[k];
      now.vertices[k] += d.segment<3>(3 * n);
      vel[k] = u.segment<3>(3 * n);
    }
    out.write_surface(b.name, frame, now, vel);
  }

  /// Each dynamic body's integrator state (NewmarkIntegrator::write_state) and energy baselines.
  void write_checkpoint(BinaryWriter& out) const override {
    out(std::uint64_t(bodies_.size()));
    for (const auto& b : bodies_) {
      b.integrator->write_state(out);
      const_cast<EnergyWatch&>(b.energy).state(out);
    }
  }
  void read_checkpoint(BinaryReader& in) override {
    in.expect_size(bodies_.size(), "solids");
    for (auto& b : bodies_) {
      b.integrator->read_state(in);
      b.energy.state(in);
    }
  }

  std::vector<double> probe(const scene::Json& p) const override {
    const auto kind = p.at("kind").get<std::string>();
    if (kind == "total_energy" && !static_) {
      double e = 0;
      for (const auto& b : bodies_) e += b.integrator->energies().total();
      return {e};
    }
    for (const auto& b : bodies_) {
      if (!p.contains("solid") || p["solid"] != b.name) continue;
      if (kind == "point_displacement") {  // the node nearest to the rest point
        const int best = nearest_node(b.model->reference_positions(), vec3(p.at("point")));
        const Eigen::Vector3d d = displacement(b).segment<3>(3 * best);
        return {d.x(), d.y(), d.z()};
      }
      if (kind == "contact_force" && !static_) {
        const Eigen::Vector3d f = b.integrator->contact_force();
        return {f.x(), f.y(), f.z()};
      }
      if (kind == "solid_volume") {
        const Eigen::VectorXd J = b.model->volume_ratios(displacement(b));
        double vol = 0;
        for (int t = 0; t < b.model->num_tets(); ++t) vol += J[t] * b.model->rest_volume(t);
        return {vol};
      }
    }
    return {};
  }

 private:
  /// What the steps of one body's step(h) cost, over its substeps.
  struct Substeps {
    int count = 0;
    int solver_iterations = 0;
    double assembly_seconds = 0, solve_seconds = 0;
  };

  /// One step of length h of body b; a step that leaves a tet inverted (volume ratio J <= 0: a
  /// contact impulse on a few nodes, or a fast rotation, that the stiffness linearised at d^n of
  /// eq. 18 cannot follow) or fails (a system matrix that is not positive definite) is undone and
  /// taken as two steps of h/2, each halved again, at most `halvings` times. The last substep's
  /// inverted tets, and a state that overflowed, are left to the watchdog (unphysical()).
  void step_or_halve(Body& b, double h, int halvings, Substeps& taken) const {
    auto& integ = *b.integrator;
    const solid::NewmarkIntegrator::State before = integ.save_state();
    bool kept = false;
    try {
      const solid::StepStats& st = integ.step(h);
      taken.solver_iterations += st.solver_iterations;
      taken.assembly_seconds += st.assembly_seconds;
      taken.solve_seconds += st.solve_seconds;
      // An overflowed state (loads far beyond the material: a volume ratio that is not finite) is
      // not a step too long; it is kept for the watchdog to name the load (inverted_tets).
      const Eigen::VectorXd J = b.model->volume_ratios(integ.displacement());
      kept = halvings == 0 || !J.allFinite() || J.minCoeff() > 0;
    } catch (const solid::SolidError&) {  // e.g. A not positive definite at a crushed state
      if (halvings == 0) throw;
    }
    if (kept) {
      taken.count += 1;  // kept (the cost of an undone step is in the times)
      return;
    }
    integ.restore_state(before);
    step_or_halve(b, 0.5 * h, halvings - 1, taken);
    step_or_halve(b, 0.5 * h, halvings - 1, taken);
  }

  const Eigen::VectorXd& displacement(const Body& b) const {
    if (!static_) return b.integrator->displacement();
    return state_at(b.steps, selected_);
  }

  std::vector<Body> bodies_;
  bool static_ = false;
  double selected_ = -1;  // static: the load factor probe() answers for (-1: the final state)
  WatchdogSettings watchdog_;
  int max_step_halvings_ = 0;  ///< /simulation/max_step_halvings
};

}  // namespace

std::unique_ptr<Simulation> make_solid_runner() { return std::make_unique<SolidRunner>(); }

}  // namespace tetfsi::run
