#include "apps/run/solid_springs.hpp"

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/tet_tools.hpp"

namespace tetfsi::run {

int add_scene_springs(solid::NewmarkIntegrator& integrator, const scene::Json& solid, int solid_index,
                      const std::string& solid_name, spdlog::logger& log) {
  if (!solid.contains("springs")) return 0;
  const Eigen::VectorXd& X = integrator.model().reference_positions();
  int added = 0;
  for (std::size_t k = 0; k < solid["springs"].size(); ++k) {
    const auto& s = solid["springs"][k];
    const std::string where = fmt::format("/solids/{}/springs/{}", solid_index, k);
    const std::string label =
        s.contains("name") ? fmt::format("spring '{}'", s["name"].get<std::string>()) : fmt::format("spring {}", k);
    std::vector<int> nodes;
    if (s.contains("region")) {
      nodes = integrator.nodes_in_box(vec3(s["region"].at("lo")), vec3(s["region"].at("hi")));
      if (nodes.empty())
        throw InputError(fmt::format("{}/region: {} of solid '{}': the box holds no node of the solid", where, label,
                                     solid_name));
    } else {
      // The node nearest to `point` (a solid always has nodes).
      const int best = nearest_node(X, vec3(s.at("point")));
      if (best < 0) throw InputError(fmt::format("{}/point: {} of solid '{}': the solid has no node", where, label, solid_name));
      nodes.push_back(best);
    }
    const double k_node = s.at("stiffness").get<double>() / static_cast<double>(nodes.size());
    for (int a : nodes) {
      solid::LinearSpring spring;
      spring.node = a;
      spring.anchor = s.contains("anchor") ? vec3(s["anchor"]) : Eigen::Vector3d(X.segment<3>(3 * a));
      spring.stiffness = k_node;
      integrator.add_spring(spring);
    }
    added += static_cast<int>(nodes.size());
    log.info("solid '{}': {} ties {} node(s) to {} with {} N/m in total", solid_name, label, nodes.size(),
             s.contains("anchor") ? "a fixed anchor" : "their rest positions", s.at("stiffness").get<double>());
  }
  return added;
}

}  // namespace tetfsi::run
