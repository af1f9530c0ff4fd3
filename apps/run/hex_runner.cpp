/// @file hex_runner.cpp
/// Solid-only scenes with Total Lagrangian hex8 solids (solid/hex, seed paper 002): /fluid/type
/// is "none", no tet solid deforms, and at least one solid has model "hex8" and motion "none".
/// Each solid's mesh is a structured block (`box` geometry) or a hex mesh file (`volume_mesh`),
/// rotated and translated by its placement (hex_geometry.hpp); condition boxes are world
/// coordinates.
///
/// `model.analysis: "static"`: load stepping with Newton-Raphson (solid/hex/static_solver.hpp)
/// from load factor 0 to 1 in `static.load_steps` steps, done in setup(); frame k of the output
/// is load step k with the load factor as its "time" in the .pvd, the per-step Newton log goes to
/// run.log and load_steps.csv (load factor, iterations, cuts, final residual ratio, reaction
/// moment of the first moment_rotation face [N m]).
/// `model.analysis: "dynamic"`: the HexModel inside the tet solid's NewmarkIntegrator
/// (Chentanez et al. 2006, eq. 18), with gravity, fixed nodes, dead loads and obstacles.
/// stats.csv (dynamic): kinetic, strain, gravity potential, total (their sum) [J], solver
/// iterations, inverted elements, contacts, and the potential of the dead loads
/// (nodal_force, traction, moment_traction) V_f = -f.d [J].
///
/// Watchdog (dynamic; watchdog.hpp): an inverted element stops the run naming it; every load is
/// conservative (gravity, constant dead loads f, fixed nodes, static obstacles), so the energy
/// E = kinetic + strain + gravity potential - f.d may only fall, and a rise past
/// max_energy_growth x its scale (at least m |g| L) stops the run.
#include <algorithm>

#include <fmt/format.h>

#include <fstream>

#include "apps/run/scene_values.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/hex_geometry.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_params.hpp"
#include "apps/run/watchdog.hpp"
#include "solid/hex/block_problem.hpp"
#include "solid/hex/hex_output.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/solid_error.hpp"

namespace tetfsi::run {
namespace {

namespace hex = solid::hex;

bool is_hex(const scene::Json& s) { return s.at("motion").at("type") == "none" && s.at("model").at("type") == "hex8"; }

/// The scene's solid as a hex::BlockProblem on its placed mesh (hex_mesh_of: a box or a file,
/// rotated and translated; the condition boxes select nodes of the placed mesh).
hex::BlockProblem problem_of(const scene::Json& s, std::vector<std::string>& warnings) {
  hex::BlockProblem p;
  p.mesh = hex_mesh_of(s, warnings);
  p.material = hex_material(s.at("material"));
  for (const auto& box : s.at("fixed_regions")) {
    hex::RegionCondition rc;
    rc.lo = vec3(box.at("lo"));
    rc.hi = vec3(box.at("hi"));
    rc.components.clear();
    for (const auto& c : box.at("components")) rc.components += c.get<std::string>();
    p.conditions.push_back(rc);
  }
  using K = hex::RegionCondition::Kind;
  const std::map<std::string, K> kinds = {{"fixed", K::Fixed},
                                          {"displacement", K::Displacement},
                                          {"nodal_force", K::NodalForce},
                                          {"traction", K::Traction},
                                          {"moment_rotation", K::MomentRotation},
                                          {"moment_traction", K::MomentTraction}};
  for (const auto& bc : s.at("boundary_conditions")) {
    hex::RegionCondition rc;
    rc.kind = kinds.at(bc.at("type").get<std::string>());
    rc.lo = vec3(bc.at("box").at("lo"));
    rc.hi = vec3(bc.at("box").at("hi"));
    rc.components = bc.at("components").get<std::string>();
    rc.value = vec3(bc.at("value"));
    rc.axis = vec3(bc.at("axis"));
    rc.center = vec3(bc.at("center"));
    rc.angle = bc.at("angle").get<double>();
    rc.moment = bc.at("moment").get<double>();
    p.conditions.push_back(rc);
  }
  const auto& st = s.at("static");
  p.options.load_steps = st.at("load_steps").get<int>();
  p.options.max_iterations = st.at("max_iterations").get<int>();
  p.options.residual_tolerance = st.at("residual_tolerance").get<double>();
  p.options.increment_tolerance = st.at("increment_tolerance").get<double>();
  p.options.max_step_cuts = st.at("max_step_cuts").get<int>();
  p.options.linear_solver = st.at("linear_solver") == "cg" ? hex::LinearSolverKind::ConjugateGradient
                                                          : hex::LinearSolverKind::Cholmod;
  return p;
}

struct HexBody {
  std::string name;
  std::unique_ptr<hex::HexModel> model;
  hex::BoundaryConditions bc;
  std::unique_ptr<solid::NewmarkIntegrator> integrator;  // dynamic only
  std::vector<double> load_factors;                          // static only: frame k
  std::vector<Eigen::VectorXd> states;                       // static only: u per load step
  std::vector<hex::StepLog> logs;
  std::vector<double> moments;                               // reaction moment per step [N m]
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
  void setup(const scene::Scene& scene, spdlog::logger& log) override {
    solid::limit_blas_threads(1);
    const auto& js = scene.json;
    const auto& sim = js.at("simulation");
    h_ = sim.contains("dt") ? sim["dt"].get<double>() : 1.0 / sim.at("frame_rate").get<double>();
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
        b.bc = hex::make_conditions(p, b.model->mesh());
        // Overlapping `fixed` regions fix an edge node's dof twice: no contradiction in a scene
        // (the solver refuses a dof constrained twice, so it gets each once).
        auto& fixed = b.bc.fixed_dofs;
        std::sort(fixed.begin(), fixed.end());
        fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
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
  double max_dt() const override { return h_; }

  StepReport setup_report() const override {
    StepReport r;
    r.phase_seconds = {assemble_, solve_};
    double steps = 0, its = 0, max_its = 0, cuts = 0;
    for (const auto& b : bodies_)
      for (const auto& l : b.logs) {
        steps += 1;
        its += l.iterations;
        max_its = std::max(max_its, double(l.iterations));
        cuts += l.cuts;
      }
    r.values = {steps, its, max_its, cuts};
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
      if (what.empty())
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
        std::ofstream csv(out.dir() / fmt::format("{}_load_steps.csv", b.name));
        csv << "load_factor,iterations,cuts,final_residual_ratio,reaction_moment\n";
        for (std::size_t k = 0; k < b.states.size(); ++k) {
          write(out, b, static_cast<int>(k), b.load_factors[k], b.states[k], Eigen::VectorXd());
          if (k == 0) continue;
          const auto& l = b.logs[k - 1];
          csv << csv_row({l.load_factor, double(l.iterations), double(l.cuts),
                          l.residuals.empty() ? 0.0 : l.residuals.back(), b.moments[k - 1]});
        }
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
    return static_ ? b.states.back() : b.integrator->displacement();
  }

  void solve_static(HexBody& b, const hex::BlockProblem& p, spdlog::logger& log) {
    b.load_factors = {0.0};
    b.states = {Eigen::VectorXd::Zero(3 * b.model->num_nodes())};
    auto on_step = [&](const hex::StepLog& l, const Eigen::VectorXd& u) {
      std::string ratios;
      for (std::size_t k = 1; k < l.residuals.size(); ++k)
        ratios += fmt::format(" {:.3g}", l.residuals[k - 1] > 0 ? l.residuals[k] / l.residuals[k - 1] : 0.0);
      log.info("hex '{}': load factor {:.6g}: {} Newton solves, {} cuts, residuals [{}], ratios [{} ]", b.name,
               l.load_factor, l.iterations, l.cuts, fmt::join(l.residuals, ", "), ratios);
      b.load_factors.push_back(l.load_factor);
      b.states.push_back(u);
      b.logs.push_back(l);
      double m = 0;
      if (!b.bc.rotating_faces.empty()) {
        Eigen::Vector3d f, mom;
        hex::face_reaction(*b.model, b.bc.rotating_faces[0], u, f, mom);
        m = mom.dot(b.bc.rotating_faces[0].axis.normalized());
      }
      b.moments.push_back(m);
    };
    try {
      const auto result = hex::solve_static(*b.model, b.bc, p.options, 1.0, on_step);
      assemble_ += result.assembly_seconds;
      solve_ += result.solve_seconds;
    } catch (const hex::NonConvergence& e) {
      throw RunError(fmt::format("hex solid '{}': static solve failed: {}", b.name, e.what()));
    } catch (const std::invalid_argument& e) {
      throw InputError(fmt::format("hex solid '{}': {}", b.name, e.what()));
    }
  }

  void make_dynamic(HexBody& b, const scene::Json& s, const scene::Json& js, const std::string& ptr) {
    if (!b.bc.prescribed.empty() || !b.bc.rotating_faces.empty())
      throw InputError(ptr + "/boundary_conditions: `displacement` and `moment_rotation` need analysis: static");
    try {
      const solid::NewmarkSettings settings = newmark_settings(s, js, h_);
      b.integrator = std::make_unique<solid::NewmarkIntegrator>(*b.model, settings);
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
  double h_ = 0, assemble_ = 0, solve_ = 0;
  bool static_ = false;
  WatchdogSettings watchdog_;
};

}  // namespace

RunnerEntry hex_runner() {
  return {"hex", "Total Lagrangian hex8 blocks without fluid (static load stepping or implicit Newmark dynamics)",
          [](const scene::Scene& s) {
            if (s["fluid"].at("type") != "none") return false;
            bool any = false;
            for (const auto& solid : s["solids"]) {
              if (solid.at("motion").at("type") == "none" && solid.at("model").at("type") == "tet_fem") return false;
              any = any || is_hex(solid);
            }
            return any;
          },
          [] { return std::make_unique<HexRunner>(); },
          {"point_displacement", "total_energy"}};
}

}  // namespace tetfsi::run
