#include "apps/run/scene_values.hpp"

#include <Eigen/Geometry>
#include <algorithm>

#include "mesh/surface_import.hpp"

namespace tetfsi::run {

Eigen::Vector3d vec3(const scene::Json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

std::array<bool, 3> fixed_components(const scene::Json& fixed_region) {
  std::array<bool, 3> held{false, false, false};
  for (const auto& c : fixed_region.at("components")) held[c.get<std::string>().at(0) - 'x'] = true;
  return held;
}

mesh::MeshSizing mesh_sizing(const scene::Json& m) {
  mesh::MeshSizing sizing;
  sizing.edge_length = m.at("edge_length").get<double>();
  sizing.edge_length_near_solids = m.at("edge_length_near_solids").get<double>();
  sizing.grading_distance = m.at("grading_distance").get<double>();
  sizing.facet_distance = m.at("facet_distance").get<double>();
  sizing.solid_feature_angle_deg = m.at("feature_angle_deg").get<double>();
  return sizing;
}

Eigen::Vector3d moved(const scene::Json& motion, const Eigen::Vector3d& x0, double t) {
  const auto type = motion.at("type").get<std::string>();
  if (type == "translation") return x0 + t * vec3(motion.at("velocity"));
  if (type == "rotation") {
    const Eigen::Vector3d c = vec3(motion.at("center"));
    const Eigen::AngleAxisd R(motion.at("angular_velocity").get<double>() * t,
                              vec3(motion.at("axis")).normalized());
    return c + R * (x0 - c);
  }
  if (type == "path") {  // piecewise-linear translation and Euler angles, held beyond the ends
    const auto& k = motion.at("keyframes");
    std::size_t i = 0;
    while (i + 2 < k.size() && t > k[i + 1]["time"].get<double>()) ++i;
    const double t0 = k[i]["time"].get<double>(), t1 = k[i + 1]["time"].get<double>();
    const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    const Eigen::Vector3d tr = (1 - s) * vec3(k[i]["translation"]) + s * vec3(k[i + 1]["translation"]);
    const Eigen::Vector3d rot = (1 - s) * vec3(k[i]["rotation_deg"]) + s * vec3(k[i + 1]["rotation_deg"]);
    return mesh::placement_rotation(rot) * x0 + tr;
  }
  return x0;
}

}  // namespace tetfsi::run
