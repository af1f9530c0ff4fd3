#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {

Field domain() {
  return box("domain",
             "The fluid box [m]. Required when `fluid.type` is not `none`; every solid must lie "
             "strictly inside it.");
}

Field mesh() {
  return Field::object("mesh", "Size controls of the tetrahedral mesh (CGAL Mesh_3).", {
      Field::number("edge_length", "m", "Target edge length far from solids.").greater(0).def(0.1),
      Field::number("edge_length_near_solids", "m",
                    "Target edge length at solid surfaces; 0 means `edge_length`.")
          .at_least(0).def(0),
      Field::number("grading_distance", "m",
                    "Distance from the solids over which the size grows to `edge_length`; 0: no grading.")
          .at_least(0).def(0),
      Field::number("facet_distance", "m",
                    "Largest distance between a mesh facet and the input surface; 0: edge length / 10.")
          .at_least(0).def(0),
  }).check([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.at("edge_length_near_solids").get<double>() > o.at("edge_length").get<double>())
      issues.push_back({pointer_append(ptr, "edge_length_near_solids"),
                        "expected a value <= edge_length (refinement near solids, not coarsening)"});
  });
}

}  // namespace tetfsi::scene::blocks
