#include "apps/run/preflight_regions.hpp"

#include <fmt/format.h>

#include "apps/run/preflight_obstacles.hpp"
#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

std::vector<scene::Issue> empty_region_issues(const scene::Json& js, const std::vector<PlacedBox>& boxes,
                                              const std::vector<ContainedSolid>& solids) {
  std::vector<scene::Issue> issues;
  const auto& declared = js.at("solids");
  for (std::size_t i = 0; i < declared.size() && i < boxes.size(); ++i) {
    if (!boxes[i].ok) continue;
    const auto& p = boxes[i];
    const double tol = 1e-9 * (p.hi - p.lo).norm();
    const auto& bcs = declared[i].at("boundary_conditions");
    // fixed_regions too (a hex8 solid's are checked on its mesh: empty_hex_regions).
    const scene::Json fixed = declared[i]["model"]["type"] == "hex8" ? scene::Json::array() : declared[i].value("fixed_regions", scene::Json::array());
    for (std::size_t j = 0; j < bcs.size() + fixed.size(); ++j) {
      const scene::Json& box = j < bcs.size() ? bcs[j].at("box") : fixed[j - bcs.size()];
      const Eigen::Vector3d lo = vec3(box.at("lo")), hi = vec3(box.at("hi"));
      if ((lo.array() <= p.hi.array() + tol).all() && (hi.array() >= p.lo.array() - tol).all() &&
          !box_outside_solid(*solids[i].surface, (lo.array() - tol).matrix(), (hi.array() + tol).matrix()))
        continue;
      issues.push_back({j < bcs.size() ? fmt::format("/solids/{}/boundary_conditions/{}/box", i, j)
                         : fmt::format("/solids/{}/fixed_regions/{}", i, j - bcs.size()),
          fmt::format("the box [{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m misses solid '{}' (bounding box "
                      "[{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m): it selects no node",
                      lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(), solids[i].name, p.lo.x(), p.lo.y(), p.lo.z(),
                      p.hi.x(), p.hi.y(), p.hi.z())});
    }
  }
  return issues;
}

}  // namespace tetfsi::run
