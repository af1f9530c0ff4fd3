/// @file kinematic_runner.cpp
/// Solids that only follow their prescribed motion (no fluid, no deformation): every solid of
/// the scene has /solids/i/motion/type other than "none" and /fluid/type is "none". Moves the
/// placed rest surfaces rigidly and exports them with per-vertex velocity, e.g. to preview a
/// scene's animation before the physics is added.
#include <fmt/format.h>

#include "apps/run/scene_values.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_geometry.hpp"
#include "support/stopwatch.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_import.hpp"

namespace tetfsi::run {
namespace {


struct Body {
  std::string name;
  mesh::SurfaceMesh rest, now;
  std::vector<Eigen::Vector3d> velocity;
  scene::Json motion;
};

class KinematicRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy& time_steps, spdlog::logger& log) override {
    for (const auto& s : scene["solids"]) {
      std::vector<std::string> warnings;
      Body b{s.at("name").get<std::string>(), surface_of(s, warnings), {}, {}, s.at("motion")};
      for (const auto& w : warnings) log.warn("{}", w);
      b.now = b.rest;
      b.velocity.assign(b.rest.vertices.size(), Eigen::Vector3d::Zero());
      bodies_.push_back(std::move(b));
    }
    move(0.0, 0.0);
    log.info("kinematic runner: {} solid(s) follow their prescribed motion; step {} s", bodies_.size(), time_steps.fixed_step());
  }

  std::vector<std::string> phases() const override { return {"move"}; }
  std::vector<std::string> columns() const override { return {"vertices", "max_speed"}; }
  double max_dt(const scene::TimeStepPolicy& time_steps) const override { return time_steps.fixed_step(); }

  StepReport step(double h) override {
    Stopwatch clock;
    time_ += h;
    move(time_, h);
    StepReport r;
    r.dt = h;
    r.phase_seconds = {clock.seconds()};
    double vertices = 0, vmax = 0;
    for (const auto& b : bodies_) {
      vertices += b.now.num_vertices();
      for (const auto& v : b.velocity) vmax = std::max(vmax, v.stableNorm());  // no overflow of |v|^2
    }
    r.values = {vertices, vmax};
    return r;
  }

  std::string non_finite() const override {
    for (const auto& b : bodies_)
      for (int i = 0; i < b.now.num_vertices(); ++i) {
        if (!b.now.vertices[i].allFinite()) return fmt::format("solid '{}': position of vertex {}", b.name, i);
        if (!b.velocity[i].allFinite()) return fmt::format("solid '{}': velocity of vertex {}", b.name, i);
      }
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    for (const auto& b : bodies_) {
      auto grid = mesh::io::make_grid(b.now);
      std::vector<double> v, u;
      for (int i = 0; i < b.now.num_vertices(); ++i) {
        v.insert(v.end(), {b.velocity[i].x(), b.velocity[i].y(), b.velocity[i].z()});
        const Eigen::Vector3d d = b.now.vertices[i] - b.rest.vertices[i];
        u.insert(u.end(), {d.x(), d.y(), d.z()});
      }
      grid.add_point_data("velocity", 3, v);
      grid.add_point_data("displacement", 3, u);
      out.write_grid(b.name, frame, time, grid);
      out.write_surface(b.name, frame, b.now, b.velocity);
    }
  }

  std::vector<double> probe(const scene::Json& p) const override {
    const auto kind = p.at("kind").get<std::string>();
    for (const auto& b : bodies_) {
      if (!p.contains("solid") || p["solid"] != b.name) continue;
      if (kind == "solid_volume") return {mesh::enclosed_volume(b.now)};
      if (kind == "point_displacement") {  // the surface vertex nearest to the rest point
        const Eigen::Vector3d x = vec3(p.at("point"));
        int best = 0;
        for (int i = 1; i < b.rest.num_vertices(); ++i)
          if ((b.rest.vertices[i] - x).squaredNorm() < (b.rest.vertices[best] - x).squaredNorm()) best = i;
        const Eigen::Vector3d d = b.now.vertices[best] - b.rest.vertices[best];
        return {d.x(), d.y(), d.z()};
      }
    }
    return {};
  }

 private:
  /// Positions at time t; velocities analytic for translation and rotation, the secant over the
  /// last step (length h) for keyframed paths.
  void move(double t, double h) {
    for (auto& b : bodies_) {
      const auto type = b.motion.at("type").get<std::string>();
      for (int i = 0; i < b.rest.num_vertices(); ++i) {
        const Eigen::Vector3d x = moved(b.motion, b.rest.vertices[i], t);
        if (type == "translation") b.velocity[i] = vec3(b.motion.at("velocity"));
        else if (type == "rotation")
          b.velocity[i] = b.motion.at("angular_velocity").get<double>() *
                          vec3(b.motion.at("axis")).normalized().cross(x - vec3(b.motion.at("center")));
        else if (h > 0) b.velocity[i] = (x - b.now.vertices[i]) / h;
        b.now.vertices[i] = x;
      }
    }
  }

  std::vector<Body> bodies_;
  double time_ = 0;
};

}  // namespace

std::unique_ptr<Simulation> make_kinematic_runner() { return std::make_unique<KinematicRunner>(); }

}  // namespace tetfsi::run
