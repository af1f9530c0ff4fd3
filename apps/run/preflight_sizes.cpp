#include "apps/run/preflight_sizes.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

namespace {
constexpr double kTetsPerCube = 8.485;  // 6 sqrt 2
constexpr double kPi = 3.14159265358979323846;

/// A box region's faces inside the domain box and off its walls [m^2].
double box_surface_area(const Eigen::Vector3d& lo_in, const Eigen::Vector3d& hi_in, const Eigen::Vector3d& dlo,
                        const Eigen::Vector3d& dhi) {
  const double on_wall = 1e-9 * (dhi - dlo).norm();  // as liquid_region_shape (fluid_setup.cpp)
  const Eigen::Vector3d lo = lo_in.cwiseMax(dlo), hi = hi_in.cwiseMin(dhi), size = (hi - lo).cwiseMax(0.0);
  double area = 0;
  for (int k = 0; k < 3; ++k) {
    const double face = size[(k + 1) % 3] * size[(k + 2) % 3];
    if (lo[k] > dlo[k] + on_wall) area += face;
    if (hi[k] < dhi[k] - on_wall) area += face;
  }
  return area;
}
}  // namespace

double free_surface_area(const scene::Json& js, const std::vector<double>& mesh_areas) {
  const auto& f = js.at("fluid");
  if (f.value("fill", "domain") != "regions" || !js.contains("domain")) return 0;
  const Eigen::Vector3d dlo = vec3(js["domain"]["lo"]), dhi = vec3(js["domain"]["hi"]), size = dhi - dlo;
  const Eigen::Vector3d g = vec3(js.at("simulation").at("gravity"));
  const Eigen::Vector3d up = g.norm() > 0 ? Eigen::Vector3d(-g.normalized()) : Eigen::Vector3d::UnitZ();
  double area = 0;
  std::size_t mesh_index = 0;
  for (const auto& r : f.at("regions")) {
    const auto type = r.at("type").get<std::string>();
    if (type == "box") {
      area += box_surface_area(vec3(r["lo"]), vec3(r["hi"]), dlo, dhi);
    } else if (type == "sphere") {
      const double radius = r.at("radius").get<double>();
      area += 4 * kPi * radius * radius + (r.contains("cap_height") ? kPi * radius * radius : 0.0);
    } else if (type == "below") {
      for (int k = 0; k < 3; ++k) area += std::abs(up[k]) * size[(k + 1) % 3] * size[(k + 2) % 3];
    } else if (mesh_index < mesh_areas.size()) {
      area += mesh_areas[mesh_index++];
    }
  }
  return area;
}

double surface_band_tets(double area, double hs, double far, double grading) {
  if (!(hs < far) || !(area > 0)) return 0;
  const double G = std::max(grading, 3 * hs);
  const double core = 3 * (1 / (hs * hs) - hs / std::pow(far, 3));
  const double ramp = G / (2 * (far - hs)) * (1 / (hs * hs) - 1 / (far * far)) - G / std::pow(far, 3);
  return kTetsPerCube * 2 * area * (core + ramp);
}

double facet_edge(double edge, double facet_distance, double curvature_radius) {
  if (!(facet_distance > 0) || !(curvature_radius > 0)) return edge;
  return std::min(edge, std::sqrt(6 * curvature_radius * facet_distance));
}

}  // namespace tetfsi::run
