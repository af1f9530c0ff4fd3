#include "apps/run/preflight_emitters.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

std::vector<std::string> emitter_warnings(const scene::Json& js, bool meshes_fluid,
                                          const std::function<void(const std::string&, double)>& check_magnitude) {
  std::vector<std::string> warnings;
  const auto& emitters = js.at("emitters");
  if (emitters.empty()) return warnings;
  if (!meshes_fluid || !js.contains("domain")) {
    warnings.push_back("/emitters: the scene has no fluid domain; its emitters do nothing");
    return warnings;
  }
  const Eigen::Vector3d lo = vec3(js["domain"]["lo"]), hi = vec3(js["domain"]["hi"]);
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    const auto& shape = emitters[i].at("shape");
    Eigen::Vector3d a, b;
    if (shape.at("type") == "box") {
      a = vec3(shape.at("lo")), b = vec3(shape.at("hi"));
    } else {
      const double r = shape.at("radius").get<double>();
      a = vec3(shape.at("center")) - Eigen::Vector3d::Constant(r), b = vec3(shape.at("center")) + Eigen::Vector3d::Constant(r);
    }
    const std::string ptr = fmt::format("/emitters/{}/shape", i);
    check_magnitude(ptr, std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()));
    const bool overlaps = (a.array() <= hi.array()).all() && (lo.array() <= b.array()).all();
    if (!overlaps)
      warnings.push_back(fmt::format("{}: the emitter lies outside the domain: it does nothing", ptr));
    else if (!((a - lo).array() >= 0).all() || !((hi - b).array() >= 0).all())
      warnings.push_back(fmt::format("{}: the emitter reaches outside the domain: only its part inside acts", ptr));
  }
  return warnings;
}

}  // namespace tetfsi::run
