#include "apps/run/preflight_probes.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "apps/run/solid_params.hpp"

namespace tetfsi::run {

std::vector<scene::Issue> probe_issues(const scene::Json& js, const std::string& runner,
                                       const std::vector<std::string>& probe_kinds) {
  std::vector<scene::Issue> issues;
  const auto& probes = js.at("probes");
  const bool any_static = [&] {
    for (const auto& s : js.at("solids"))
      if (s.at("motion").at("type") == "none" && is_static(s)) return true;
    return false;
  }();
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const auto kind = probes[i].at("kind").get<std::string>();
    const auto& kinds = probe_kinds;
    const bool supported = kinds.empty() || std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
    if (!supported || (any_static && (kind == "total_energy" || kind == "contact_force"))) {
      std::string list;
      for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
      issues.push_back({fmt::format("/probes/{}/kind", i),
          fmt::format("the {} runner (which runs this scene) has no probe \"{}\"; it has: {}", runner, kind,
                      any_static ? "point_displacement, solid_volume (tet_fem) in a static analysis" : list)});
    }
  }
  return issues;
}

}  // namespace tetfsi::run
