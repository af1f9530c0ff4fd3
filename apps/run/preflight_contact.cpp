#include "apps/run/preflight_contact.hpp"

#include <fmt/format.h>

namespace tetfsi::run {
std::vector<scene::Issue> contact_gap_issues(const scene::Json& js, const std::string& runner,
                                             const std::vector<PlacedBox>& boxes, const Eigen::Vector3d& lo,
                                             const Eigen::Vector3d& hi) {
  std::vector<scene::Issue> issues;
  if (runner != "coupled" || !js.contains("coupling")) return issues;
  const auto& c = js["coupling"];
  const double gap = c.value("contact_gap", 0.0);
  // A film on two opposite walls that meets in the middle leaves no room for anything, whether
  // or not a solid moves (checked before the per-solid test, which skips fixed solids).
  const double narrowest = (hi - lo).minCoeff();
  if (gap > 0 && narrowest > 0 && 2 * gap >= narrowest) {
    issues.push_back({"/coupling/contact_gap",
        fmt::format("the fluid film of {:g} m on two opposite walls is at least the domain's narrowest extent "
                    "({:.4g} m): lower /coupling/contact_gap below half of it",
                    gap, narrowest)});
    return issues;
  }
  // A film given for contacts that are all off contradicts itself.
  if (gap > 0 && !c.value("wall_contact", true)) {
    bool pairs = c.value("solid_contact", true) && js["solids"].size() > 1;
    for (const auto& s : js["solids"]) pairs = pairs || s.value("self_contact", false);
    const auto& obstacles = js.value("obstacles", scene::Json::object());
    const bool others = !obstacles.value("planes", scene::Json::array()).empty() || !obstacles.value("boxes", scene::Json::array()).empty();
    if (!pairs && !others)
      issues.push_back({"/coupling/contact_gap",
          fmt::format("a fluid film of {:g} m is given, but no contact keeps it: /coupling/wall_contact is false and "
                      "there is no contact between solids (/coupling/solid_contact with two or more solids, "
                      "/solids/*/self_contact) and no /obstacles; remove contact_gap or turn a contact on",
                      gap)});
  }
  if (js["domain"].contains("container")) return issues;
  if (!c.value("wall_contact", true) || !(gap > 0)) return issues;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const auto& p = boxes[i];
    const auto& solid = js["solids"][i];
    if (!p.ok || !solid.value("fixed_regions", scene::Json::array()).empty() ||
        solid["motion"].value("type", "none") != "none")
      continue;
    if (((p.lo - lo).array() >= gap).all() && ((hi - p.hi).array() >= gap).all()) continue;
    issues.push_back({"/coupling/contact_gap",
        fmt::format("solid '{}' starts closer than the wall film of {:g} m to the domain's walls (bounding box "
                    "[{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m): lower /coupling/contact_gap or move "
                    "/solids/{}/placement",
                    js["solids"][i]["name"].get<std::string>(), gap, p.lo.x(), p.lo.y(), p.lo.z(), p.hi.x(), p.hi.y(), p.hi.z(), i)});
  }
  return issues;
}

}  // namespace tetfsi::run
