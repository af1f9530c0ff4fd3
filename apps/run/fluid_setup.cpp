#include "apps/run/fluid_setup.hpp"

#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

fluid::FluidParams fluid_params(const scene::Json& js, spdlog::logger& log) {
  const auto& f = js.at("fluid");
  fluid::FluidParams params;
  params.density = f.at("density").get<double>();
  params.gravity = vec3(js.at("simulation").at("gravity"));
  params.apply_gravity = f.at("apply_gravity").get<bool>();
  if (f.at("type") == "smoke") {
    params.buoyancy.alpha = f.at("buoyancy_alpha").get<double>();
    params.buoyancy.beta = f.at("buoyancy_beta").get<double>();
    params.buoyancy.ambient_temperature = f.at("ambient_temperature").get<double>();
    params.vorticity_epsilon = f.at("vorticity_confinement").get<double>();
  }
  const auto adv = f.at("advection").get<std::string>();
  params.advection = adv == "bfecc"             ? fluid::AdvectionScheme::kBfecc
                     : adv == "semi_lagrangian" ? fluid::AdvectionScheme::kSemiLagrangian
                                                : fluid::AdvectionScheme::kLinear;
  params.solver.backend = fluid::parse_solver_backend(f.at("solver").at("type").get<std::string>());
  params.solver.tolerance = f.at("solver").at("tolerance").get<double>();
  params.solver.max_iterations = f.at("solver").at("max_iterations").get<int>();
  if (f.at("viscosity").get<double>() > 0)
    log.info("/fluid/viscosity = {} is not used: the fluid model is inviscid", f.at("viscosity").get<double>());
  return params;
}

std::vector<fluid::BoundaryPatch> boundary_patches(const scene::Json& js, double ambient) {
  std::vector<fluid::BoundaryPatch> patches;
  const Eigen::Vector3d lo = vec3(js.at("domain").at("lo")), hi = vec3(js.at("domain").at("hi"));
  for (const auto& in : js["domain"].at("inflows")) {
    fluid::BoundaryPatch p;
    p.region = {vec3(in.at("lo")), vec3(in.at("hi"))};
    p.kind = fluid::FaceKind::kInflow;
    p.velocity = vec3(in.at("velocity"));
    p.smoke = in.at("smoke_density").get<double>();
    const double T = in.at("temperature").get<double>();
    p.temperature = T > 0 ? T : ambient;
    patches.push_back(p);
  }
  const double eps = 1e-6 * (hi - lo).norm();
  for (const auto& face : js["domain"].at("open_faces")) {
    const auto name = face.get<std::string>();
    const int axis = name[0] - 'x';
    fluid::BoundaryPatch p;
    p.kind = fluid::FaceKind::kOpen;
    p.region = {lo, hi};
    if (name[1] == '+') p.region.lo[axis] = hi[axis] - eps;
    else p.region.hi[axis] = lo[axis] + eps;
    patches.push_back(p);
  }
  return patches;
}

std::vector<TimedSource> timed_sources(const scene::Json& js, spdlog::logger& log) {
  std::vector<TimedSource> out;
  for (std::size_t i = 0; i < js.at("emitters").size(); ++i) {
    const auto& e = js["emitters"][i];
    TimedSource em;
    const auto& shape = e.at("shape");
    if (shape.at("type") == "box") {
      em.source.region = {vec3(shape.at("lo")), vec3(shape.at("hi"))};
    } else {
      const Eigen::Vector3d c = vec3(shape.at("center"));
      const double r = shape.at("radius").get<double>();
      em.source.region = {c.array() - r, c.array() + r};
      log.warn("/emitters/{}: a sphere source acts on the tets whose centroid lies in its bounding box", i);
    }
    em.source.smoke = e.at("smoke_density").get<double>();
    em.source.temperature = e.at("temperature").get<double>();
    em.source.velocity = vec3(e.at("velocity"));
    em.source.set_velocity = em.source.velocity.norm() > 0;
    em.start = e.at("start_time").get<double>();
    if (e.contains("end_time")) em.end = e["end_time"].get<double>();
    out.push_back(em);
  }
  return out;
}

}  // namespace tetfsi::run
