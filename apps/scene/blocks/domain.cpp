#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {
namespace {

/// The fluid container when it is not the domain box: a sphere or a cylinder, checked to lie inside
/// [lo, hi] of the domain (the bounding box the inflows, emitters and probes refer to).
Field container() {
  return Field::object("container",
                       "The shape of the fluid's vessel; absent or `box`: the domain box itself. A `sphere`, "
                       "`cylinder` or `mesh` container must lie inside the domain box; its surface is a slip wall "
                       "(no flux), apart from `inflows` and `open_patches` (by region, as for the box); "
                       "`open_faces` name box faces and need the box. Meshed as a polyhedron: an icosphere or a "
                       "prism over a regular polygon inscribed in the exact shape, or the file's triangles. "
                       "Wall contact (/coupling/wall_contact) holds solids off every container's walls (for a "
                       "`mesh`: the signed distance to its triangles).", {
      Field::enumeration("type", {"box", "sphere", "cylinder", "mesh"},
                         "`box`: the domain box; `sphere`, `cylinder`: the primitive below; `mesh`: a closed "
                         "surface file (OBJ, PLY, STL, glTF, FBX, OFF), its inside the fluid.").req(),
  }).tagged_by("type")
    .variant("box", {})
    .variant("sphere", {
        Field::vector("center", 3, "m", "Centre.").req(),
        Field::number("radius", "m", "Radius.").req().greater(0),
        Field::integer("subdivisions", "Icosphere subdivisions of the surface (20 * 4^n triangles).")
            .at_least(1).at_most(6).def(3)})
    .variant("cylinder", {
        Field::vector("center", 3, "m", "Centre (midpoint of the axis).").req(),
        Field::number("radius", "m", "Radius.").req().greater(0),
        Field::number("length", "m", "Length along the axis, cap to cap.").req().greater(0),
        Field::enumeration("axis", {"x", "y", "z"}, "Axis direction.").def("z"),
        Field::integer("segments", "Sides of the polygon the circle is meshed as.").at_least(8).at_most(512).def(48)})
    .variant("mesh", {
        Field::file("file", "Closed, manifold surface file, relative to the scene file's folder; its triangles "
                            "are the container's walls.").req(),
        Field::number("unit_scale", "m/unit", "Metres per file unit (0.01 for files in cm).").greater(0).def(1.0),
        Field::vector("rotation_deg", 3, "deg", "Euler XYZ rotation (about x, then y, then z), after the scale.")
            .def({0, 0, 0}),
        Field::vector("translation", 3, "m", "Translation, applied last.").def({0, 0, 0})});
}

/// A moving wall moves in its own plane: its velocity has no component along the thinnest extent
/// of its patch (the normal of the box face it covers).
void tangential_wall_velocity(const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
  if (!o.contains("lo") || !o.contains("hi") || !o.contains("velocity")) return;
  int thin = 0;
  for (int k = 1; k < 3; ++k)
    if (o["hi"][k].get<double>() - o["lo"][k].get<double>() < o["hi"][thin].get<double>() - o["lo"][thin].get<double>())
      thin = k;
  const double normal = o["velocity"][thin].get<double>();
  if (normal != 0)
    issues.push_back({pointer_append(ptr, "velocity"),
                      fmt::format("a moving wall moves in its own plane, but its velocity has {} m/s along {}, the "
                                  "patch's thinnest extent (the wall normal); set it to 0 (use an inflow patch for "
                                  "flow through the wall)",
                                  normal, char('x' + thin))});
}

/// The container (if a sphere or cylinder) inside the domain box, and no open faces with it.
void check_container(const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
  if (!o.contains("container") || !o["container"].is_object()) return;
  const auto& c = o["container"];
  const auto type = c.value("type", "box");
  if (type == "box") return;
  if (o.contains("open_faces") && !o["open_faces"].empty())
    issues.push_back({pointer_append(ptr, "open_faces"),
                      fmt::format("open faces name faces of the domain box; a {} container has none (its surface "
                                  "is a wall; use `open_patches` and `inflows` patches)", type)});
  // A mesh container's extent is checked against the box once its file is read (preflight.cpp).
  if (!c.contains("center") || !c.contains("radius") || !o.contains("lo") || !o.contains("hi")) return;
  const double r = c["radius"].get<double>();
  std::array<double, 3> half{r, r, r};
  if (type == "cylinder" && c.contains("length"))
    half[c.value("axis", "z")[0] - 'x'] = 0.5 * c["length"].get<double>();
  for (int k = 0; k < 3; ++k) {
    const double x = c["center"][k].get<double>();
    if (x - half[k] < o["lo"][k].get<double>() || x + half[k] > o["hi"][k].get<double>()) {
      issues.push_back({pointer_append(ptr, "container"),
                        fmt::format("the {} container reaches outside the domain box along {} ([{:.4g}, {:.4g}] m "
                                    "vs the box's [{:.4g}, {:.4g}] m); enlarge /domain or shrink the container",
                                    type, char('x' + k), x - half[k], x + half[k], o["lo"][k].get<double>(),
                                    o["hi"][k].get<double>())});
      return;
    }
  }
}

}  // namespace

Field domain() {
  Field inflow = Field::object("", "", {
      Field::vector("lo", 3, "m", "Lower corner of the patch region.").req(),
      Field::vector("hi", 3, "m", "Upper corner of the patch region.").req(),
      Field::vector("velocity", 3, "m/s", "Inflow velocity.").req(),
      Field::number("smoke_density", "", "Smoke concentration of the inflow.").at_least(0).def(0),
      Field::number("temperature", "K", "Temperature of the inflow; 0: ambient.").at_least(0).def(0),
      Field::enumeration("profile", {"uniform", "parabolic"},
                         "`uniform`: `velocity` on every face of the patch; `parabolic`: a pipe (Poiseuille) "
                         "profile u = velocity (1 - r^2/R^2), r the distance of a point from the patch's axis "
                         "(the line through the centre of [lo, hi] along `velocity`), R half the smaller extent of "
                         "[lo, hi] across `velocity` (the disc inscribed in the patch), 0 beyond R: `velocity` is "
                         "the peak, the mean over the disc is half of it.").def("uniform")});
  inflow.checks.push_back(lo_below_hi());
  Field open_patch = Field::object("", "", {
      Field::vector("lo", 3, "m", "Lower corner of the patch region.").req(),
      Field::vector("hi", 3, "m", "Upper corner of the patch region.").req()});
  open_patch.checks.push_back(lo_below_hi());
  Field moving_wall = Field::object("", "", {
      Field::vector("lo", 3, "m", "Lower corner of the patch region.").req(),
      Field::vector("hi", 3, "m", "Upper corner of the patch region.").req(),
      Field::vector("velocity", 3, "m/s",
                    "Velocity of the wall, tangential to it (its component along the patch's thinnest extent, "
                    "the wall normal of a box face, must be 0).").req()});
  moving_wall.checks.push_back(lo_below_hi());
  moving_wall.checks.push_back(tangential_wall_velocity);
  return Field::object("domain",
                       "The fluid box [m]. Required when `fluid.type` is not `none`; every solid must lie "
                       "strictly inside it (and inside `container`). Box faces are walls (no flux) unless "
                       "listed in `open_faces` or covered by an `inflows` or `open_patches` patch. With a "
                       "`container` sphere, cylinder or mesh the fluid fills that shape, and the box only bounds "
                       "it.", {
      Field::vector("lo", 3, "m", "Lower corner.").req(),
      Field::vector("hi", 3, "m", "Upper corner (> lo in every coordinate).").req(),
      Field::array("open_faces", "Box faces with pressure 0 (flow leaves or enters freely).",
                   Field::enumeration("", {"x-", "x+", "y-", "y+", "z-", "z+"}, "A box face."))
          .def(Json::array()),
      Field::array("slip_faces",
                   "Box faces on which a viscous fluid slips although `fluid.walls` is `no_slip` (symmetry "
                   "planes: a thin slab with slip faces front and back is a 2D flow).",
                   Field::enumeration("", {"x-", "x+", "y-", "y+", "z-", "z+"}, "A box face."))
          .def(Json::array()),
      Field::array("inflows",
                   "Inflow patches: boundary faces of the container whose centroid lies in [lo, hi] get "
                   "the prescribed velocity, smoke and temperature (first match wins, before open patches "
                   "and open faces). With a free-surface liquid (fluid.fill `regions`) a patch pours "
                   "liquid: the layer one edge length deep in front of it is kept full of liquid moving "
                   "at its velocity, and what it adds is added to the volume the run keeps.",
                   std::move(inflow))
          .def(Json::array()),
      Field::array("moving_walls",
                   "Walls that move in their own plane (the lid of a driven cavity, the plate of Couette "
                   "flow): boundary faces whose centroid lies in [lo, hi] are walls (no flux) whose velocity a "
                   "viscous fluid takes (`fluid.viscosity` > 0); after the inflows, before open patches.",
                   std::move(moving_wall))
          .def(Json::array()),
      Field::array("open_patches",
                   "Open patches of any container: boundary faces whose centroid lies in [lo, hi] have "
                   "pressure 0 (flow leaves or enters freely), after the inflows and before the open faces.",
                   std::move(open_patch))
          .def(Json::array()),
      container(),
  }).check(lo_below_hi()).check(check_container);
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
