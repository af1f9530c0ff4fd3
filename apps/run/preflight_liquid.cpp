#include "apps/run/preflight_liquid.hpp"

#include <functional>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "apps/run/container.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/fluid_setup.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/solid_geometry.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_distance.hpp"

namespace tetfsi::run {
namespace {

constexpr int kLattice = 24;  ///< points per axis over a region's bounding box

/// The region's bounding box [lo, hi] [m] (the whole domain box for `below`).
void region_bounds(const scene::Json& region, const Eigen::Vector3d& domain_lo, const Eigen::Vector3d& domain_hi,
                   Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  const auto type = region.at("type").get<std::string>();
  lo = domain_lo;
  hi = domain_hi;
  if (type == "box") {
    lo = vec3(region.at("lo"));
    hi = vec3(region.at("hi"));
  } else if (type == "sphere") {
    const Eigen::Vector3d c = vec3(region.at("center"));
    const double r = region.at("radius").get<double>();
    lo = c.array() - r;
    hi = c.array() + r;
  } else if (type == "mesh") {
    std::vector<std::string> warnings;
    mesh::bounding_box(liquid_region_surface(region, warnings), lo, hi);
  }
}

std::string box_text(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return fmt::format("[{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(),
                     hi.z());
}

}  // namespace

std::vector<scene::Issue> liquid_region_issues(const scene::Json& js, const std::vector<ContainedSolid>& solids) {
  std::vector<scene::Issue> issues;
  if (!js.contains("domain") || !js.contains("fluid") || js["fluid"].value("type", "none") != "liquid" ||
      js["fluid"].value("fill", "domain") != "regions")
    return issues;
  const auto& regions = js["fluid"].at("regions");
  if (regions.empty()) return issues;  // refused by the schema
  const auto& domain = js["domain"];
  const Eigen::Vector3d dlo = vec3(domain.at("lo")), dhi = vec3(domain.at("hi"));
  std::unique_ptr<mesh::SurfaceDistance> container;
  std::string container_type = "box";
  if (domain.contains("container") && domain["container"].at("type") != "box") {
    container_type = domain["container"]["type"].get<std::string>();
    try {
      container = std::make_unique<mesh::SurfaceDistance>(container_surface(domain));
    } catch (const std::exception&) {
      return issues;  // the container's own check reports it
    }
  }
  std::vector<std::unique_ptr<mesh::SurfaceDistance>> solid_distance(solids.size());
  for (std::size_t s = 0; s < solids.size(); ++s)
    if (solids[s].surface) solid_distance[s] = std::make_unique<mesh::SurfaceDistance>(*solids[s].surface);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const std::string ptr = fmt::format("/fluid/regions/{}", i);
    std::function<double(const Eigen::Vector3d&)> inside_region;
    Eigen::Vector3d lo, hi;
    try {
      inside_region = liquid_region_shape(js, i);
      region_bounds(regions[i], dlo, dhi, lo, hi);
    } catch (const std::exception&) {
      continue;  // a broken surface file: reported at /fluid/regions/i/file
    }
    lo = lo.cwiseMax(dlo);
    hi = hi.cwiseMin(dhi);
    const std::string domain_text = "the domain box " + box_text(dlo, dhi);
    if (!(lo.array() < hi.array()).all()) {
      issues.push_back({ptr, "the region lies outside " + domain_text + ": it holds no liquid"});
      continue;
    }
    // Points at the centres of a lattice over the part of the bounding box inside the domain.
    int in_region = 0, in_container = 0, in_fluid = 0, holding_solid = -1;
    const Eigen::Vector3d cell = (hi - lo) / kLattice;
    for (int a = 0; a < kLattice; ++a)
      for (int b = 0; b < kLattice; ++b)
        for (int c = 0; c < kLattice; ++c) {
          const Eigen::Vector3d x = lo + cell.cwiseProduct(Eigen::Vector3d(a + 0.5, b + 0.5, c + 0.5));
          if (!(inside_region(x) < 0)) continue;
          ++in_region;
          if (container && !((*container)(x) < 0)) continue;
          ++in_container;
          int solid = -1;
          for (std::size_t s = 0; s < solids.size() && solid < 0; ++s)
            if (solid_distance[s] && (*solid_distance[s])(x) < 0) solid = static_cast<int>(s);
          if (solid < 0) ++in_fluid;
          else if (holding_solid < 0) holding_solid = solid;
        }
    if (in_fluid > 0) continue;
    if (in_region == 0)
      issues.push_back({ptr, "the region holds no liquid: none of it lies inside " + domain_text});
    else if (in_container == 0)
      issues.push_back({ptr, fmt::format("the region lies outside the {} container /domain/container: it holds no "
                                         "liquid", container_type)});
    else
      issues.push_back({ptr, fmt::format("the region lies inside solid '{}' (/solids/{}): it holds no liquid",
                                         solids[holding_solid].name, holding_solid)});
  }
  return issues;
}

}  // namespace tetfsi::run
