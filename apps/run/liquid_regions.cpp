// The liquid regions' signed distances (fluid_setup.hpp), in a file of their own: the scene checks
// use them (preflight_liquid.cpp) and must not pull the fluid solver into `tetfsi validate`
// (apps/cli/front.cpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "apps/run/fluid_setup.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/solid_geometry.hpp"
#include "fluid/liquid/level_set.hpp"
#include "mesh/surface_distance.hpp"

namespace tetfsi::run {

std::function<double(const Eigen::Vector3d&)> liquid_region_shape(const scene::Json& scene, std::size_t i) {
  const scene::Json& r = scene.at("fluid").at("regions").at(i);
  const Eigen::Vector3d gravity = vec3(scene.at("simulation").at("gravity"));
  const Eigen::Vector3d up = gravity.norm() > 0 ? Eigen::Vector3d(-gravity.normalized()) : Eigen::Vector3d::UnitZ();
  const auto type = r.at("type").get<std::string>();
  if (type == "box") {
    const Eigen::Vector3d domain_lo = vec3(scene.at("domain").at("lo")), domain_hi = vec3(scene.at("domain").at("hi"));
    const double diagonal = (domain_hi - domain_lo).norm(), on_wall = 1e-9 * diagonal;
    Eigen::Vector3d lo = vec3(r.at("lo")), hi = vec3(r.at("hi"));
    for (int k = 0; k < 3; ++k) {  // faces on or beyond a wall moved a diagonal out
      if (lo[k] <= domain_lo[k] + on_wall) lo[k] = std::min(lo[k], domain_lo[k] - diagonal);
      if (hi[k] >= domain_hi[k] - on_wall) hi[k] = std::max(hi[k], domain_hi[k] + diagonal);
    }
    return [lo, hi](const Eigen::Vector3d& x) { return fluid::box_distance(x, lo, hi); };
  }
  if (type == "sphere") {
    const Eigen::Vector3d c = vec3(r.at("center"));
    const double radius = r.at("radius").get<double>();
    // With a cap: the intersection with the half-space below it, max(d_sphere, x·up − cap) (exact
    // inside, a lower bound outside).
    const double cap = r.contains("cap_height") ? r["cap_height"].get<double>() : std::numeric_limits<double>::infinity();
    return [c, radius, up, cap](const Eigen::Vector3d& x) { return std::max((x - c).norm() - radius, x.dot(up) - cap); };
  }
  if (type == "mesh") {
    std::vector<std::string> warnings;  // already reported by the preflight
    auto inside = std::make_shared<mesh::SurfaceDistance>(liquid_region_surface(r, warnings));
    return [inside](const Eigen::Vector3d& x) { return (*inside)(x); };
  }
  const double height = r.at("height").get<double>();  // below
  return [up, height](const Eigen::Vector3d& x) { return x.dot(up) - height; };
}

std::function<double(const Eigen::Vector3d&)> liquid_region_distance(const scene::Json& scene) {
  std::vector<std::function<double(const Eigen::Vector3d&)>> shapes;
  for (std::size_t i = 0; i < scene.at("fluid").at("regions").size(); ++i) shapes.push_back(liquid_region_shape(scene, i));
  return [shapes](const Eigen::Vector3d& x) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& s : shapes) d = std::min(d, s(x));
    return d;
  };
}

}  // namespace tetfsi::run
