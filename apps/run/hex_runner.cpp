/// @file hex_runner.cpp
/// Solid-only scenes with Total Lagrangian hex8 solids (solid/hex, Bathe 1996, sec. 6.3.2): /fluid/type
/// is "none", no tet solid deforms, and at least one solid has model "hex8" and motion "none".
/// Each solid's mesh is a structured block (`box` geometry) or a hex mesh file (`volume_mesh`),
/// rotated and translated by its placement (hex_geometry.hpp); condition boxes are world
/// coordinates.
///
/// `model.analysis: "static"`: load stepping with Newton-Raphson (solid/analysis/static_solver.hpp,
/// static_steps.hpp) from load factor 0 to 1 in `static.load_steps` steps, done in setup(); frame k
/// of the output and probes.csv row k are load step k with the load factor as their "time", the
/// per-step Newton log goes to run.log and load_steps.csv (load factor, iterations, cuts, final
/// residual ratio, reaction moment of the first moment_rotation face [N m]).
/// `model.analysis: "dynamic"`: the HexModel inside the tet solid's NewmarkIntegrator
/// (Chentanez et al. 2006, eq. 18), with gravity, fixed nodes, dead loads and obstacles.
/// stats.csv (dynamic): kinetic, strain, gravity potential, total (their sum) [J], solver
/// iterations, inverted elements, contacts, and the potential of the dead loads
/// (nodal_force, traction, moment_traction, body_force) V_f = -f.d [J]. A follower `pressure` is
/// folded into the model (solid::FollowerLoadedModel); it does work, so such a block's energy is not
/// watched.
///
/// Watchdog (dynamic; watchdog.hpp): an inverted element stops the run naming it; every load is
/// conservative (gravity, constant dead loads f, fixed nodes, static obstacles), so the energy
/// E = kinetic + strain + gravity potential - f.d may only fall, and a rise past
/// max_energy_growth x its scale (at least m |g| L) stops the run.
#include <algorithm>

#include <fmt/format.h>

#include "apps/run/scene_values.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/hex_geometry.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_params.hpp"
#include "apps/run/static_steps.hpp"
#include "apps/run/watchdog.hpp"
#include "solid/hex/block_problem.hpp"
#include "solid/hex/hex_output.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/loads/follower_pressure.hpp"
#include "solid/solid_error.hpp"

namespace tetfsi::run {
namespace {

namespace hex = solid::hex;

/// The scene's solid as a hex::BlockProblem on its placed mesh (hex_mesh_of: a box or a file,
/// rotated and translated; the condition boxes select nodes of the placed mesh).
hex::BlockProblem problem_of(const scene::Json& s, std::vector<std::string>& warnings) {
  hex::BlockProblem p;
  p.mesh = hex_mesh_of(s, warnings);
  p.material = hex_material(s.at("material"));
  p.formulation = s.at("model").value("formulation", "enhanced") == "standard" ? hex::Hex8Formulation::Standard
                                                                              : hex::Hex8Formulation::Enhanced;
  p.conditions = region_conditions(s, true);
  p.options = static_options(s);
  return p;
}

struct HexBody {
  std::string name;
  std::unique_ptr<hex::HexModel> model;
  solid::BoundaryConditions bc;
  std::unique_ptr<solid::FollowerLoadedModel> loaded;      // dynamic with pressure only
  std::unique_ptr<solid::NewmarkIntegrator> integrator;  // dynamic only
  StaticSteps steps;                                         // static only: frame k = load step k
  mesh::SurfaceMesh surface;  // boundary quads split in triangles (hex-mesh node indices)
  int index = 0;               // /solids/index
  std::string scheme;          // /solids/index/integrator/scheme (dynamic only)
  EnergyWatch energy;          // dynamic only: energy balance with the dead loads' work
};

/// Potential of the dead loads, V_f = -f.d [J] (their work is f.d).
double load_potential(const HexBody& b) {
  return b.bc.forces.size() > 0 ? -b.bc.forces.dot(b.integrator->displacement()) : 0.0;
}

class HexRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy&, spdlog::logger& log) override {
    solid::limit_blas_threads(1);
    const auto& js = scene.json;
    const auto& sim = js.at("simulation");
    bool any_static = false, any_dynamic = false;
    for (std::size_t i = 0; i < js.at("solids").size(); ++i) {
      const auto& s = js["solids"][i];
      if (!is_hex(s)) {
        log.warn("solid '{}' is kinematic and is left out of the hex runner", s.at("name").get<std::string>());
        continue;
      }
      const std::string ptr = fmt::format("/solids/{}", i);
      HexBody b;
      b.name = s.at("name").get<std::string>();
      b.index = static_cast<int>(i);
      std::vector<std::string> warnings;
      const hex::BlockProblem p = problem_of(s, warnings);
      for (const auto& w : warnings) log.warn("{}", w);
      try {
        b.model = hex::make_model(p);
        b.bc = hex::make_conditions(p, *b.model);
      } catch (const std::exception& e) {
        throw InputError(fmt::format("{}: {}", ptr, e.what()));
      }
      const auto& hm = b.model->mesh();
      b.surface = hex_boundary_surface(hm);
      log.info("hex solid '{}': {} hexes{}, {} nodes", b.name, hm.num_hexes(),
               s["geometry"]["type"] == "volume_mesh" ? " from " + s["geometry"]["file"].get<std::string>() : "",
               hm.num_vertices());
      if (s["model"].at("analysis") == "static") {
        any_static = true;
        solve_static(b, p, log);
      } else {
        any_dynamic = true;
        make_dynamic(b, s, js, ptr);
      }
      bodies_.push_back(std::move(b));
    }
    if (any_static && any_dynamic)
      throw InputError("/solids: hex8 solids of one scene must all use the same `analysis` (static or dynamic)");
    static_ = any_static;
    watchdog_ = watchdog_settings(sim);
  }

  bool time_dependent() const override { return !static_; }
  std::vector<std::string> phases() const override { return {"assemble", "solve"}; }
  std::vector<std::string> columns() const override {
    if (static_) return {"load_steps", "newton_iterations", "max_iterations_per_step", "step_cuts"};
    return {"kinetic", "strain", "gravity_potential", "total_energy", "solver_iterations", "inverted", "contacts",
            "load_potential"};
  }
  double max_dt(const scene::TimeStepPolicy& time_steps) const override { return time_steps.fixed_step(); }
  std::vector<double> load_factors() const override {
    return static_ && !bodies_.empty() ? bodies_.front().steps.load_factors : std::vector<double>{};
  }
  void select_load_step(int k) override { selected_ = load_factors().at(k); }

  StepReport setup_report() const override {
    StepReport r;
    r.phase_seconds = {assemble_, solve_};
    std::vector<const StaticSteps*> steps;
    for (const auto& b : bodies_) steps.push_back(&b.steps);
    r.values = static_totals(steps);
    return r;
  }

  StepReport step(double h) override {
    StepReport r;
    r.dt = h;
    std::vector<double> v(8, 0.0);
    double a = 0, s = 0;
    for (auto& b : bodies_) {
      try {
        const auto& st = b.integrator->step(h);  // the driver may shorten a step to land on a frame
        a += st.assembly_seconds;
        s += st.solve_seconds;
        const double loads = load_potential(b);
        b.energy.record(st.total() + loads, st.kinetic + st.strain + st.spring);
        const double vals[] = {st.kinetic, st.strain, st.gravity_potential, st.total(),
                               double(st.solver_iterations), double(st.inverted), double(st.contacts), loads};
        for (int k = 0; k < 8; ++k) v[k] += vals[k];
      } catch (const solid::SolidError& e) {
        throw RunError(fmt::format("hex solid '{}': {}", b.name, e.what()));
      }
    }
    r.phase_seconds = {a, s};
    r.values = v;
    return r;
  }

  std::string non_finite() const override {
    for (const auto& b : bodies_) {
      const Eigen::VectorXd& d = displacement(b);
      for (int i = 0; i < d.size(); ++i)
        if (!std::isfinite(d[i])) return fmt::format("hex solid '{}': displacement of node {}", b.name, i / 3);
    }
    return "";
  }

  std::string unphysical() const override {
    if (static_) return "";
    for (const auto& b : bodies_) {
      auto what = inverted_hexes(*b.model, b.integrator->displacement(), b.name, b.index);
      if (what.empty() && !b.loaded)  // a follower pressure does work: the energy is not watched
        what = b.energy.diagnosis(
            fmt::format("hex solid '{}'", b.name), "kinetic + strain + gravitational - work of the loads",
            "every load on it is conservative (gravity, dead loads, fixed nodes, static obstacles)",
            fmt::format("Lower /simulation/dt{}", b.scheme == "trapezoidal"
                                                       ? fmt::format(", use /solids/{}/integrator/scheme \"chentanez\" "
                                                                     "(dissipative)", b.index)
                                                       : fmt::format(" or soften /solids/{}/material (a stiff body "
                                                                     "needs a short step)", b.index)),
            watchdog_);
      if (!what.empty()) return what;
    }
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    for (const auto& b : bodies_) {
      if (static_) {  // every load step, "time" = load factor
        write_load_steps(out, b.name, b.steps);
        for (std::size_t k = 0; k < b.steps.states.size(); ++k)
          write(out, b, static_cast<int>(k), b.steps.load_factors[k], b.steps.states[k], Eigen::VectorXd());
      } else {
        write(out, b, frame, time, b.integrator->displacement(), b.integrator->velocity());
      }
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
      if (!p.contains("solid") || p["solid"] != b.name || kind != "point_displacement") continue;
      const Eigen::Vector3d x = vec3(p.at("point"));
      const auto& X = b.model->reference_positions();
      int best = 0;
      for (int i = 1; i < b.model->num_nodes(); ++i)
        if ((X.segment<3>(3 * i) - x).squaredNorm() < (X.segment<3>(3 * best) - x).squaredNorm()) best = i;
      const Eigen::Vector3d d = displacement(b).segment<3>(3 * best);
      return {d.x(), d.y(), d.z()};
    }
    return {};
  }

 private:
  const Eigen::VectorXd& displacement(const HexBody& b) const {
    if (!static_) return b.integrator->displacement();
    return state_at(b.steps, selected_);
  }

  void solve_static(HexBody& b, const hex::BlockProblem& p, spdlog::logger& log) {
    b.steps = solve_in_steps(b.name, *b.model, b.bc, p.options, log);
    assemble_ += b.steps.assembly_seconds;
    solve_ += b.steps.solve_seconds;
  }

  void make_dynamic(HexBody& b, const scene::Json& s, const scene::Json& js, const std::string& ptr) {
    if (!b.bc.prescribed.empty() || !b.bc.rotating_faces.empty())
      throw InputError(ptr + "/boundary_conditions: `displacement` and `moment_rotation` need analysis: static");
    try {
      const solid::NewmarkSettings settings = newmark_settings(s, js);
      const solid::ElasticModel* model = b.model.get();
      if (!b.bc.pressures.empty()) {  // follower pressure folded into the model's force
        b.loaded = std::make_unique<solid::FollowerLoadedModel>(*b.model, b.bc.pressures);
        model = b.loaded.get();
      }
      b.integrator = std::make_unique<solid::NewmarkIntegrator>(*model, settings);
    } catch (const solid::SolidError& e) {
      throw InputError(fmt::format("{}: {}", ptr, e.what()));
    }
    std::vector<int> count(b.model->num_nodes(), 0), nodes;
    for (int dof : b.bc.fixed_dofs) ++count[dof / 3];  // each dof once (setup)
    for (int n = 0; n < b.model->num_nodes(); ++n) {
      if (count[n] == 3) nodes.push_back(n);
      else if (count[n] > 0)
        throw InputError(ptr + "/boundary_conditions: fixing single components needs analysis: static");
    }
    if (!nodes.empty()) b.integrator->fix_nodes(nodes);
    if (b.bc.forces.size() > 0) b.integrator->set_external_forces(b.bc.forces);
    b.integrator->set_uniform_velocity(vec3(s.at("initial_velocity")));
    const auto& obs = js.at("obstacles");
    for (const auto& pl : obs.at("planes")) b.integrator->obstacles().add_plane({vec3(pl.at("point")), vec3(pl.at("normal"))});
    for (const auto& bx : obs.at("boxes")) b.integrator->obstacles().add_box({vec3(bx.at("lo")), vec3(bx.at("hi"))});
    b.integrator->obstacles().set_friction(obs.at("friction").get<double>());
    b.scheme = s.at("integrator").at("scheme").get<std::string>();
    // The floor is m |g| L only: the dead loads' work shows in the scale as soon as they move the
    // block (a floor |f| L would hide any error of their work f.d, which stays far below it).
    const double weight = b.model->lumped_masses().sum() * vec3(js.at("simulation").at("gravity")).norm();
    const auto e = b.integrator->energies();
    b.energy = EnergyWatch(e.total() + load_potential(b), e.kinetic + e.strain + e.spring,
                           energy_floor(b.model->reference_positions(), weight));
  }

  void write(Output& out, const HexBody& b, int frame, double time, const Eigen::VectorXd& d,
             const Eigen::VectorXd& u) {
    try {
      auto grid = hex::make_hex_grid(*b.model, d);
      if (u.size() > 0) grid.add_point_data("velocity", 3, std::vector<double>(u.data(), u.data() + u.size()));
      out.write_grid(b.name, frame, time, grid);
    } catch (const std::runtime_error& e) {
      throw RunError(fmt::format("hex solid '{}': {}", b.name, e.what()));
    }
    mesh::SurfaceMesh now = b.surface;
    std::vector<Eigen::Vector3d> vel(now.vertices.size(), Eigen::Vector3d::Zero());
    for (std::size_t k = 0; k < now.vertices.size(); ++k) {
      now.vertices[k] += d.segment<3>(3 * k);
      if (u.size() > 0) vel[k] = u.segment<3>(3 * k);
    }
    out.write_surface(b.name, frame, now, vel);
  }

  std::vector<HexBody> bodies_;
  double assemble_ = 0, solve_ = 0;
  bool static_ = false;
  double selected_ = -1;  // static: the load factor probe() answers for (-1: the final state)
  WatchdogSettings watchdog_;
};

}  // namespace

std::unique_ptr<Simulation> make_hex_runner() { return std::make_unique<HexRunner>(); }

}  // namespace tetfsi::run
