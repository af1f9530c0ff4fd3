#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {

Field domain() {
  Field inflow = Field::object("", "", {
      Field::vector("lo", 3, "m", "Lower corner of the patch region.").req(),
      Field::vector("hi", 3, "m", "Upper corner of the patch region.").req(),
      Field::vector("velocity", 3, "m/s", "Inflow velocity.").req(),
      Field::number("smoke_density", "", "Smoke concentration of the inflow.").at_least(0).def(0),
      Field::number("temperature", "K", "Temperature of the inflow; 0: ambient.").at_least(0).def(0)});
  inflow.checks.push_back(lo_below_hi());
  return Field::object("domain",
                       "The fluid box [m]. Required when `fluid.type` is not `none`; every solid must lie "
                       "strictly inside it. Box faces are walls (no flux) unless listed in `open_faces` "
                       "or covered by an `inflows` patch.", {
      Field::vector("lo", 3, "m", "Lower corner.").req(),
      Field::vector("hi", 3, "m", "Upper corner (> lo in every coordinate).").req(),
      Field::array("open_faces", "Box faces with pressure 0 (flow leaves or enters freely).",
                   Field::enumeration("", {"x-", "x+", "y-", "y+", "z-", "z+"}, "A box face."))
          .def(Json::array()),
      Field::array("inflows",
                   "Inflow patches: boundary faces of the box whose centroid lies in [lo, hi] get the "
                   "prescribed velocity, smoke and temperature (first match wins, before open faces).",
                   std::move(inflow))
          .def(Json::array()),
  }).check(lo_below_hi());
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
      Field::number("feature_angle_deg", "deg",
                    "Solid edges whose facet normals differ by more than this are kept sharp; -1: "
                    "automatic (60 for piecewise-flat solids such as boxes and sheets, none for smooth "
                    "or scanned ones); 0: none (corners are rounded, which avoids flat tets in thin "
                    "sheets).")
          .at_least(-1).at_most(180).def(-1),
  }).check([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.at("edge_length_near_solids").get<double>() > o.at("edge_length").get<double>())
      issues.push_back({pointer_append(ptr, "edge_length_near_solids"),
                        "expected a value <= edge_length (refinement near solids, not coarsening)"});
  });
}

}  // namespace tetfsi::scene::blocks
