/// @file fluid_runner.cpp
/// Smoke or liquid in the domain box, around solids that are static or follow a prescribed motion
/// (fluid/README.md, "What a scene runner needs"). Deformable solids (motion `none`) belong to the
/// coupled runner and are not accepted here.
///
/// Set-up: one CGAL complex of the container (the domain box or /domain/container) and every solid
/// (mesh_container in container.hpp, sizes from /mesh).
/// A solid whose motion is a zero translation or zero rotation is static: the mesh is kept for the
/// whole run. Otherwise, every step: the solid vertices move to x(t) = motion(rest position, t),
/// mesh::remesh_step carries the fluid vertices along and, when the moved mesh has degraded,
/// remeshes the fluid within /fluid/remesh_band of the degraded tets with the solids frozen, and the
/// FluidSolver steps onto the new mesh with u.n = v_solid.n on the interface (v = the motion's
/// velocity at each solid vertex).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include "apps/run/container.hpp"
#include "apps/run/fluid_columns.hpp"
#include "apps/run/fluid_probe.hpp"
#include "apps/run/fluid_setup.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_geometry.hpp"
#include "apps/run/surface_refinement.hpp"
#include "support/stopwatch.hpp"
#include "fluid/advection/point_locator.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/io/fluid_output.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid/stable_step.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/surface_import.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesh_region.hpp"
#include "mesh/remesher.hpp"

namespace tetfsi::run {
namespace {


/// Velocity [m/s] at time t of the point with rest position x0: analytic for translation and
/// rotation, the secant over [t - h, t] for keyframed paths.
Eigen::Vector3d motion_velocity(const scene::Json& motion, const Eigen::Vector3d& x0, double t, double h) {
  const auto type = motion.at("type").get<std::string>();
  if (type == "translation") return vec3(motion.at("velocity"));
  if (type == "rotation")
    return motion.at("angular_velocity").get<double>() *
           vec3(motion.at("axis")).normalized().cross(moved(motion, x0, t) - vec3(motion.at("center")));
  if (type == "path" && h > 0) return (moved(motion, x0, t) - moved(motion, x0, t - h)) / h;
  return Eigen::Vector3d::Zero();
}

bool is_static(const scene::Json& motion) {
  const auto type = motion.at("type").get<std::string>();
  if (type == "translation") return vec3(motion.at("velocity")).norm() == 0.0;
  if (type == "rotation") return motion.at("angular_velocity").get<double>() == 0.0;
  return false;
}


class FluidRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy&, spdlog::logger& log) override {
    log_ = &log;
    const auto& js = scene.json;
    const auto& f = js.at("fluid");

    // ---- fluid parameters, boundary patches, emitters (fluid_setup.hpp) ----
    const fluid::FluidParams params = fluid_params(js, log);
    ambient_ = params.buoyancy.ambient_temperature > 0 ? params.buoyancy.ambient_temperature : ambient_;
    bc_.patches = boundary_patches(js, ambient_);
    emitters_ = timed_sources(js, log);

    // ---- mesh ----
    const auto& m = js.at("mesh");
    mesh::MeshSizing sizing = mesh_sizing(m);
    // A free surface with surface_edge_length: finer near the liquid (surface_refinement.hpp).
    refinement_ = surface_refinement(js);
    if (refinement_.on())
      sizing.size_at = refinement_.field(liquid_region_distance(js));
    std::vector<mesh::SurfaceMesh> surfaces;
    for (const auto& s : js.at("solids")) {
      names_.push_back(s.at("name").get<std::string>());
      motions_.push_back(s.at("motion"));
      if (!is_static(s.at("motion"))) moving_ = true;
      std::vector<std::string> warnings;
      surfaces.push_back(surface_of(s, warnings));
      for (const auto& w : warnings) log.warn("{}", w);
    }
    Stopwatch clock;
    try {
      complex_ = mesh_container(js.at("domain"), surfaces, sizing);
    } catch (const mesh::MeshError& e) {
      throw meshing_failure(e, names_);
    }
    rest_ = complex_.vertices;
    const auto q = mesh::quality_report(complex_, mesh::kFluidSubdomain);
    min_dihedral_ = q.min_dihedral_deg;
    log.info("fluid runner: {} fluid, {} tets ({} fluid), meshed in {:.2f} s; fluid quality: {}",
             f.at("type").get<std::string>(), complex_.num_tets(), q.num_tets, clock.seconds(), q.summary());
    if (js["domain"].contains("container") && js["domain"]["container"]["type"] != "box") {
      double volume = 0;  // of the fluid tets [m^3]
      for (int k = 0; k < complex_.num_tets(); ++k)
        if (complex_.subdomain[k] == mesh::kFluidSubdomain) volume += mesh::signed_volume(complex_, k);
      log.info("fluid container: {} (slip walls), fluid volume {:.6g} m^3",
               js["domain"]["container"]["type"].get<std::string>(), volume);
    }
    remesh_.target_edge_length = mesh::mean_edge_length(complex_, mesh::kFluidSubdomain);
    remesh_.band = f.at("remesh_band").get<double>();
    // Move, remesh when needed: while the carried-along mesh stays good (fluid min dihedral above
    // the threshold, no tet's volume changed by more than 2x in the step) it is kept as is; the
    // "remeshed" column of stats.csv says which steps were remeshed. Then only the fluid within
    // remesh_band of the spoiled tets is remeshed (adaptive band).
    remesh_.remesh_only_when_needed = true;
    remesh_.adaptive_band = true;
    if (moving_)
      log.info("kinematic solids: the fluid moves with them, remeshed when needed (target edge {:.4g} m, band {} m)",
               remesh_.target_edge_length, remesh_.band);

    solver_ = std::make_unique<fluid::FluidSolver>(params);
    fluid::FluidFields fields;
    const int nt = q.num_tets;
    fields.velocity.assign(nt, Eigen::Vector3d::Zero());
    fields.smoke = Eigen::VectorXd::Zero(nt);
    fields.temperature = Eigen::VectorXd::Constant(nt, ambient_);
    try {
      solver_->initialize(complex_, fields);
    } catch (const std::invalid_argument& e) {
      throw RunError(std::string("fluid initialisation failed: ") + e.what());
    }
    try {
      set_initial_liquid(js, *solver_, log);
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("/fluid/regions: ") + e.what());
    }
    dx_ = solver_->mesh().mean_edge_length();
    update_solid_velocity(0.0, 0.0);
    if (refinement_.on()) {
      refinement_.mark(*solver_);
      log.info("{}", refinement_.summary());
    }
  }

  std::vector<std::string> phases() const override {
    std::vector<std::string> p = {"remesh", "advect", "forces", "assemble", "solve"};
    add_fluid_phases(*solver_, p);
    return p;
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c = {"tets", "nodes", "unknowns", "iterations", "residual", "max_divergence",
                                  "kinetic_energy", "gravity_potential", "min_dihedral", "clamped_traces", "remeshed",
                                  "remeshed_tets"};
    add_fluid_columns(*solver_, c);
    return c;
  }

  /// The scene's `dt`, or the CFL step (fluid/stable_step.hpp) on the fluid's mean edge length,
  /// with the moving solids' speed and the free-fall bound of a liquid, at most one frame.
  double max_dt(const scene::TimeStepPolicy& time_steps) const override {
    if (time_steps.dt) return *time_steps.dt;
    return fluid::cfl_step(*solver_, time_steps.cfl, dx_, max_solid_speed_, time_steps.frame_interval(), true);
  }

  StepReport step(double h) override {
    time_ += h;
    Stopwatch clock;
    remeshed_ = false;
    remeshed_tets_ = 0;
    surface_fitted_ = false;
    if (refinement_.on()) remesh_.size_at = refinement_.current_field(*solver_);
    if (surface_left_refined_zone_ && !moving_) remesh_for_surface();
    if (moving_) {
      std::vector<Eigen::Vector3d> target = complex_.vertices;
      for (std::size_t v = 0; v < target.size(); ++v)
        if (vertex_solid_[v] >= 0) target[v] = moved(motions_[vertex_solid_[v]], rest_[v], time_);
      // remesh_step returns its last pass even when the quality check failed. A fluid tet that
      // is flat or inverted would break the pressure matrix: then remesh again from the moved
      // mesh with more CGAL iterations, the last time over the whole fluid instead of a band. A
      // positive but small minimum dihedral angle is only reported.
      // The surface left its refined zone: remesh where the mesh no longer fits the liquid
      // surface's sizing field, with the band around the moving solids (the whole fluid without
      // a band, or on a second attempt).
      std::vector<char> misfit;
      if (surface_left_refined_zone_) misfit = misfit_tets();
      mesh::RemeshResult r;
      mesh::QualityReport q;
      for (int attempt = 0;; ++attempt) {
        mesh::RemeshOptions opt = remesh_;
        if (!misfit.empty() && attempt == 0) {
          opt.remesh_only_when_needed = false;
          opt.remesh_tets = misfit;
          const std::vector<char> near_solids = mesh::band_tets(complex_, opt.band);
          for (std::size_t t = 0; t < near_solids.size(); ++t) opt.remesh_tets[t] |= near_solids[t];
        } else if (!misfit.empty()) {
          opt.band = 0;
          opt.remesh_only_when_needed = false;
        }
        opt.iterations += 2 * attempt;
        if (attempt == 2) opt.band = 0;
        try {
          r = mesh::remesh_step(complex_, target, opt);
        } catch (const mesh::MeshError& e) {
          throw RunError(fmt::format("remeshing at t = {} s failed: {} (reduce simulation.dt or cfl)", time_, e.what()));
        }
        q = mesh::quality_report(r.mesh, mesh::kFluidSubdomain);
        if (q.inverted + q.degenerate == 0) break;
        if (attempt == 2)
          throw RunError(fmt::format("remeshing at t = {} s left {} inverted and {} flat fluid tets ({})", time_,
                                     q.inverted, q.degenerate, r.report.summary()));
        log_->warn("t = {} s: remesh left {} inverted and {} flat fluid tets; remeshing again with {} iterations",
                   time_, q.inverted, q.degenerate, opt.iterations + 2);
      }
      if (!r.report.quality_ok)
        log_->warn("t = {} s: fluid min dihedral angle {:.3g} deg is below {} deg", time_, q.min_dihedral_deg,
                   remesh_.min_dihedral_deg);
      log_->debug("t = {} s: remesh {}", time_, r.report.summary());
      std::vector<Eigen::Vector3d> rest(r.mesh.num_vertices());
      for (int v = 0; v < r.mesh.num_vertices(); ++v)
        rest[v] = r.old_index[v] >= 0 ? rest_[r.old_index[v]] : r.mesh.vertices[v];
      rest_ = std::move(rest);
      complex_ = std::move(r.mesh);
      min_dihedral_ = r.report.min_dihedral_deg;
      remeshed_ = r.report.remeshed;
      if (remeshed_) remeshed_tets_ = r.report.remeshed_fluid_tets;
      if (!misfit.empty()) surface_fitted_ = remeshed_;
      update_solid_velocity(time_, h);
    }
    const double t_remesh = clock.seconds();

    fluid::BoundaryConditions bc = bc_;
    for (const auto& e : emitters_)
      if (e.active(time_ - h)) bc.sources.push_back(e.source);
    bc.solid_vertex_velocity = solid_velocity_;
    fluid::StepReport s;
    try {
      s = solver_->step(complex_, bc, h);
    } catch (const std::exception& e) {  // SolverError, non-finite values, bad boundary input
      throw RunError(fmt::format("fluid step at t = {} s failed: {}", time_, e.what()));
    }
    last_ = s;
    if (refinement_.on()) {
      if (surface_fitted_) refinement_.mark(*solver_);
      surface_left_refined_zone_ = refinement_.left_zone(solver_->level_set());
    }
    dx_ = solver_->mesh().mean_edge_length();

    StepReport rep;
    rep.dt = h;
    rep.phase_seconds = {t_remesh, s.advect_seconds, s.forces_seconds, s.assemble_seconds, s.solve_seconds};
    rep.values = {double(s.num_tets), double(s.num_nodes), double(s.unknowns), double(s.iterations), s.residual,
                  s.max_divergence, s.kinetic_energy, s.gravity_potential, min_dihedral_, double(s.clamped_traces),
                  double(remeshed_), double(remeshed_tets_)};
    add_fluid_values(*solver_, s, rep.phase_seconds, rep.values);
    return rep;
  }

  std::string non_finite() const override {
    const auto& fl = solver_->fields();
    for (std::size_t t = 0; t < fl.velocity.size(); ++t)
      if (!fl.velocity[t].allFinite()) return fmt::format("fluid velocity of tet {}", t);
    for (Eigen::Index t = 0; t < fl.smoke.size(); ++t)
      if (!std::isfinite(fl.smoke[t]) || !std::isfinite(fl.temperature[t]))
        return fmt::format("fluid smoke or temperature of tet {}", t);
    for (Eigen::Index n = 0; n < solver_->pressure().size(); ++n)
      if (!std::isfinite(solver_->pressure()[n])) return fmt::format("fluid pressure of node {}", n);
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    // The solver's mesh is the one moved to the solids at t^{n+1} before the step (remesh_step
    // above), the positions of this frame's solid surfaces: no lag to correct.
    write_fluid_frame(out, frame, time, *solver_, solver_->mesh().nodes);
    for (std::size_t i = 0; i < names_.size(); ++i) {
      std::vector<Eigen::Vector3d> vel;
      const auto surface = solid_surface(static_cast<int>(i), vel);
      out.write_surface(names_[i], frame, surface, vel);
    }
  }

  /// The fluid solver's state, the mesh with its rest positions and solid velocities, the CFL cell
  /// size and the last step's kinetic energy (no surface refinement: see fluid_runner()).
  void write_checkpoint(BinaryWriter& out) const override {
    solver_->write_state(out);
    out(complex_.vertices, complex_.tets, complex_.subdomain, rest_, vertex_solid_, solid_velocity_, remeshed_,
        remeshed_tets_, dx_, time_, max_solid_speed_, min_dihedral_, last_.kinetic_energy);
  }
  void read_checkpoint(BinaryReader& in) override {
    solver_->read_state(in);
    in(complex_.vertices, complex_.tets, complex_.subdomain, rest_, vertex_solid_, solid_velocity_, remeshed_,
       remeshed_tets_, dx_, time_, max_solid_speed_, min_dihedral_, last_.kinetic_energy);
    const std::size_t n = complex_.vertices.size();
    if (rest_.size() != n || vertex_solid_.size() != n || solid_velocity_.size() != n)
      in.fail("a fluid-runner mesh whose vertex arrays differ in size");
  }

  std::vector<double> probe(const scene::Json& p) const override {
    const auto kind = p.at("kind").get<std::string>();
    if (kind == "fluid_kinetic_energy") return {last_.kinetic_energy};
    if (kind == "fluid_volume") {
      if (solver_->has_free_surface()) return {solver_->liquid().total_volume()};
      double v = 0;
      for (double x : solver_->mesh().volume) v += x;
      return {v};
    }
    if (kind == "fluid_force") {
      const auto solid = std::find(names_.begin(), names_.end(), p.at("solid").get<std::string>());
      if (solid == names_.end()) return {};
      const int subdomain = mesh::solid_subdomain(static_cast<int>(solid - names_.begin()));
      const std::string part = p.value("part", "total");
      Eigen::Vector3d f = Eigen::Vector3d::Zero();
      if (part != "viscous") f += solver_->pressure_force(subdomain);
      if (part != "pressure") f += solver_->viscous_force(subdomain);
      return {f.x(), f.y(), f.z()};
    }
    if (kind != "fluid_point") return {};
    return {fluid_point_value(*solver_, p)};
  }

 private:
  /// Remeshes the fluid (solids frozen) with the sizing field of the current surface where it
  /// moved since the last fit (misfit_tets; the whole fluid if that region is not a ball);
  /// the solver carries the fields and the level set over in its next step.
  void remesh_for_surface() {
    mesh::RemeshOptions opt = remesh_;
    opt.remesh_only_when_needed = false;
    opt.band = 0;
    opt.target_edge_length = refinement_.far_edge();
    opt.remesh_tets = misfit_tets();
    if (opt.remesh_tets.empty()) return;
    mesh::RemeshResult r;
    try {
      r = mesh::remesh_step(complex_, complex_.vertices, opt);
    } catch (const mesh::MeshError& e) {
      throw RunError(fmt::format("remeshing for the liquid surface at t = {} s failed: {}", time_, e.what()));
    }
    const mesh::QualityReport q = mesh::quality_report(r.mesh, mesh::kFluidSubdomain);
    if (q.inverted + q.degenerate > 0) {
      log_->warn("t = {} s: remeshing for the liquid surface left {} inverted and {} flat tets; kept the old mesh",
                 time_, q.inverted, q.degenerate);
      return;
    }
    std::vector<Eigen::Vector3d> rest(r.mesh.num_vertices());
    for (int v = 0; v < r.mesh.num_vertices(); ++v)
      rest[v] = r.old_index[v] >= 0 ? rest_[r.old_index[v]] : r.mesh.vertices[v];
    rest_ = std::move(rest);
    complex_ = std::move(r.mesh);
    min_dihedral_ = q.min_dihedral_deg;
    remeshed_ = true;
    surface_fitted_ = true;
    remeshed_tets_ = r.report.remeshed_fluid_tets;
    update_solid_velocity(time_, 0.0);
    log_->debug("t = {} s: remeshed for the liquid surface: {}", time_, r.report.summary());
  }

  /// The fluid tets where the liquid surface's sizing field moved since the last fit
  /// (SurfaceRefinement::resized_tets), or none: then the mesh fits the surface as it is, and the
  /// step records the fit anew.
  std::vector<char> misfit_tets() {
    std::vector<char> misfit = refinement_.resized_tets(complex_, remesh_.size_at);
    if (misfit.empty()) surface_fitted_ = true;
    return misfit;
  }

  /// Which solid each complex vertex belongs to (-1: fluid only), and the solid vertex velocities.
  void update_solid_velocity(double t, double h) {
    vertex_solid_.assign(complex_.num_vertices(), -1);
    for (int k = 0; k < complex_.num_tets(); ++k)
      if (complex_.subdomain[k] >= mesh::solid_subdomain(0))
        for (int v : complex_.tets[k]) vertex_solid_[v] = complex_.subdomain[k] - mesh::solid_subdomain(0);
    solid_velocity_.assign(complex_.num_vertices(), Eigen::Vector3d::Zero());
    max_solid_speed_ = 0;
    for (int v = 0; v < complex_.num_vertices(); ++v)
      if (vertex_solid_[v] >= 0 && !is_static(motions_[vertex_solid_[v]])) {
        solid_velocity_[v] = motion_velocity(motions_[vertex_solid_[v]], rest_[v], t, h);
        max_solid_speed_ = std::max(max_solid_speed_, solid_velocity_[v].norm());
      }
  }

  /// Outward boundary surface of solid i's tets in the complex, with the vertex velocities.
  mesh::SurfaceMesh solid_surface(int i, std::vector<Eigen::Vector3d>& velocity) const {
    std::map<std::array<int, 3>, std::array<int, 4>> faces;  // sorted face -> (oriented face, opposite)
    static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (int k = 0; k < complex_.num_tets(); ++k) {
      if (complex_.subdomain[k] != mesh::solid_subdomain(i)) continue;
      const auto& t = complex_.tets[k];
      for (int f = 0; f < 4; ++f) {
        std::array<int, 3> key{t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]]};
        std::array<int, 3> sorted = key;
        std::sort(sorted.begin(), sorted.end());
        auto it = faces.find(sorted);
        if (it != faces.end()) faces.erase(it);
        else faces[sorted] = {key[0], key[1], key[2], t[f]};
      }
    }
    mesh::SurfaceMesh s;
    std::map<int, int> index;
    auto id = [&](int v) {
      auto [it, added] = index.emplace(v, static_cast<int>(s.vertices.size()));
      if (added) {
        s.vertices.push_back(complex_.vertices[v]);
        velocity.push_back(solid_velocity_[v]);
      }
      return it->second;
    };
    for (const auto& [key, f] : faces) {
      const Eigen::Vector3d &a = complex_.vertices[f[0]], &b = complex_.vertices[f[1]], &c = complex_.vertices[f[2]];
      const bool outward = (b - a).cross(c - a).dot(complex_.vertices[f[3]] - a) < 0;
      const int i0 = id(f[0]), i1 = id(f[1]), i2 = id(f[2]);
      s.triangles.push_back(outward ? std::array<int, 3>{i0, i1, i2} : std::array<int, 3>{i0, i2, i1});
    }
    return s;
  }

  spdlog::logger* log_ = nullptr;
  std::unique_ptr<fluid::FluidSolver> solver_;
  fluid::BoundaryConditions bc_;
  std::vector<TimedSource> emitters_;
  mesh::TetMesh complex_;
  std::vector<Eigen::Vector3d> rest_;  ///< rest (t = 0) position of every complex vertex (used for solid vertices)
  std::vector<int> vertex_solid_;
  std::vector<Eigen::Vector3d> solid_velocity_;
  std::vector<std::string> names_;
  std::vector<scene::Json> motions_;
  mesh::RemeshOptions remesh_;
  fluid::StepReport last_;
  bool moving_ = false;
  bool remeshed_ = false;  ///< last step remeshed the fluid (false: static, or moved only)
  int remeshed_tets_ = 0;  ///< fluid tets the last step handed to CGAL to remesh (0: none)
  SurfaceRefinement refinement_;             ///< the mesh finer at the liquid surface (off without one)
  bool surface_left_refined_zone_ = false;   ///< remesh for the surface at the start of the next step
  bool surface_fitted_ = false;              ///< this step fitted the mesh to the surface's sizing field
  double dx_ = 0;  ///< the fluid's mean edge length [m], the CFL cell
  double time_ = 0, ambient_ = 293.15;
  double max_solid_speed_ = 0, min_dihedral_ = 0;
};

}  // namespace

std::unique_ptr<Simulation> make_fluid_runner() { return std::make_unique<FluidRunner>(); }

}  // namespace tetfsi::run
