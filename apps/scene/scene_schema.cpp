#include <set>

#include <fmt/format.h>

#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene {
namespace {

// Checks across blocks: names are unique, probes name existing solids, a fluid needs a domain.
void check_scene(const Json& s, const std::string&, std::vector<Issue>& issues) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < s["solids"].size(); ++i) {
    const auto name = s["solids"][i]["name"].get<std::string>();
    if (name.empty() || name.find_first_of("/\\ ") != std::string::npos)
      issues.push_back({fmt::format("/solids/{}/name", i),
                        "expected a non-empty name without spaces or slashes (it names output files)"});
    else if (!names.insert(name).second)
      issues.push_back({fmt::format("/solids/{}/name", i), fmt::format("duplicate solid name \"{}\"", name)});
  }
  for (std::size_t i = 0; i < s["probes"].size(); ++i) {
    const auto& p = s["probes"][i];
    if (p.contains("solid") && !names.count(p["solid"].get<std::string>()))
      issues.push_back({fmt::format("/probes/{}/solid", i),
                        fmt::format("no solid named \"{}\" in /solids", p["solid"].get<std::string>())});
  }
  if (!s.contains("domain") && s["solids"].empty())
    issues.push_back({"/solids", "the scene has neither a domain nor any solid: nothing to simulate"});
  if (s["fluid"]["type"] != "none" && !s.contains("domain"))
    issues.push_back({"/domain", fmt::format("missing: a {} fluid needs a domain box {{\"lo\": [...], \"hi\": [...]}}",
                                             s["fluid"]["type"].get<std::string>())});
}

Field build() {
  return Field::object("", "A tetfsi scene.", {
      Field::string("description", "Free text shown in run.log."),
      blocks::simulation().req(),
      blocks::domain(),
      blocks::mesh(),
      blocks::fluid(),
      blocks::solids(),
      blocks::coupling(),
      blocks::obstacles(),
      blocks::emitters(),
      blocks::probes(),
      blocks::output(),
  }).check(check_scene);
}

}  // namespace

const Field& scene_schema() {
  static const Field schema = build();
  return schema;
}

}  // namespace tetfsi::scene
