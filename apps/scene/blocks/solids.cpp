#include <fmt/format.h>

#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {
namespace {

Field geometry() {
  return Field::object("geometry", "The solid's rest shape, before `placement`.", {
      Field::enumeration("type", {"mesh", "volume_mesh", "box", "sphere", "cylinder", "sheet", "bowl", "sphere_shell"},
                         "`mesh`: a closed surface file (OBJ, PLY, STL, glTF, FBX, OFF); `volume_mesh`: a "
                         "tetrahedral (model `tet_fem`) or hexahedral (model `hex8`) mesh file (VTK .vtu, Gmsh "
                         ".msh 2.2/4.1 ASCII) used as the solid's FEM mesh as it is (solid-only scenes); `box`, "
                         "`sphere`, `sheet`: primitives centred at the origin; `cylinder`: a circular "
                         "cylinder (a disc or a rod) along y, centred at the origin; `bowl`: a hemispherical "
                         "shell open toward +y, its spheres' centre at the origin and its rim in the plane "
                         "y = 0; `sphere_shell`: a hollow "
                         "sphere whose wall is the solid and whose cavity (radius - thickness) is filled "
                         "with the scene's fluid (coupled scenes only; see `fluid.fill`).").req(),
  }).tagged_by("type")
    .variant("mesh", {
        Field::file("file", "Surface file, relative to the scene file's folder.").req(),
        Field::number("unit_scale", "m/unit", "Metres per file unit (0.01 for files in cm).")
            .greater(0).def(1.0)})
    .variant("volume_mesh", {
        Field::file("file", "Volume mesh file, relative to the scene file's folder: .vtu (ASCII, inline binary "
                            "or raw appended data) with VTK_TETRA cells only (model `tet_fem`) or VTK_HEXAHEDRON "
                            "cells only (model `hex8`); .msh (Gmsh 2.2 or 4.1 ASCII) with 4-node tets only or "
                            "8-node hexahedra only, lower-dimensional elements ignored. Checked before use: "
                            "positive volume (every hex positive at its 8 corners), no repeated or duplicate "
                            "nodes, one connected piece (unused nodes are dropped, a mesh numbered mirror-wise "
                            "throughout is reordered).").req(),
        Field::number("unit_scale", "m/unit", "Metres per file unit (0.001 for files in mm).")
            .greater(0).def(1.0)})
    .variant("box", {Field::vector("size", 3, "m", "Edge lengths along x, y, z.").req().greater(0)})
    .variant("sphere", {
        Field::number("radius", "m", "Sphere radius.").req().greater(0),
        Field::integer("subdivisions", "Icosphere subdivisions of the surface (20 * 4^n triangles).")
            .at_least(0).at_most(7).def(3)})
    .variant("cylinder", {
        Field::number("radius", "m", "Radius.").req().greater(0),
        Field::number("length", "m", "Extent along y (the axis).").req().greater(0),
        Field::integer("segments", "Sides of the regular polygon inscribed in the circle.").at_least(3).at_most(1024)
            .def(32)})
    .variant("sheet", {
        Field::vector("size", 2, "m", "Extent along x and z.").req().greater(0),
        Field::number("thickness", "m", "Extent along y.").req().greater(0)})
    .variant("bowl", {
        Field::number("radius", "m", "Outer radius.").req().greater(0),
        Field::number("thickness", "m", "Wall thickness (< radius).").req().greater(0),
        Field::integer("segments", "Vertices around each latitude ring.").at_least(3).at_most(1024).def(32),
        Field::integer("rings", "Latitude rings from the bottom to the rim.").at_least(1).at_most(256).def(8)})
    .variant("sphere_shell", {
        Field::number("radius", "m", "Outer radius.").req().greater(0),
        Field::number("thickness", "m", "Wall thickness (< radius); the cavity radius is radius - thickness.")
            .req().greater(0),
        Field::integer("subdivisions", "Icosphere subdivisions of both surfaces (20 * 4^n triangles).")
            .at_least(0).at_most(7).def(3)})
    .check([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
      if ((o.at("type") == "sphere_shell" || o.at("type") == "bowl") && o.contains("radius") && o.contains("thickness") &&
          !(o["thickness"].get<double>() < o["radius"].get<double>()))
        issues.push_back({pointer_append(ptr, "thickness"),
                          fmt::format("expected a wall thickness < radius ({} m), got {} m (no cavity left)",
                                      o["radius"].get<double>(), o["thickness"].get<double>())});
    });
}

Field fixed_region() {
  Field f = box("", "");
  f.members.push_back(Field::enumeration_set("components", {"x", "y", "z"},
                                             "Displacement components held at 0, e.g. [\"y\"] or [\"x\", \"z\"].")
                          .def(Json::array({"x", "y", "z"})));
  f.members.push_back(Field::vector("velocity", 3, "m/s",
                                    "Prescribed velocity of the held components (a driven region: its "
                                    "displacement grows as velocity x t); [0, 0, 0] holds them in place. "
                                    "`tet_fem` solids only.")
                          .def({0, 0, 0}));
  return f;
}

Field material() {
  return Field::object("material", "Elastic material.", {
      Field::number("density", "kg/m^3", "Mass density.").req().greater(0),
      youngs_modulus("Young's modulus E."),
      Field::number("poissons_ratio", "", "Poisson's ratio nu (-1 < nu < 0.5).").req().greater(-1).less(0.5),
      Field::enumeration("constitutive",
                         {"stvk", "neohookean", "neohookean_bonet_wood", "neohookean_stable", "neohookean_split"},
                         "Hyperelastic law, the same on tet and hex8 elements (solid/laws/hyperelastic_law.hpp), "
                         "with lambda, mu the Lame parameters of E and nu, J = det F, I1 = tr(F^T F), "
                         "E = (F^T F - I)/2; each has the linear-elastic small-strain limit. `stvk`: "
                         "St. Venant-Kirchhoff, W = lambda/2 tr(E)^2 + mu E:E (collapses under strong "
                         "compression). `neohookean_bonet_wood`: Bonet & Wood 1997 eq. 6.28, "
                         "W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 (J > 0). `neohookean_stable`: "
                         "Smith, de Goes & Kim 2018 without the log term, W = mu/2 (I1 - 3) + "
                         "lambda'/2 (J - a)^2 + const, lambda' = lambda + mu, a = 1 + mu/lambda' (smooth "
                         "through inversion, which pushes inverted tets back). `neohookean_split`: the "
                         "isochoric/volumetric form of Abaqus and CalculiX, W = C10 (J^(-2/3) I1 - 3) + "
                         "(J - 1)^2 / D1 with C10 = mu/2, D1 = 2/K, K = E/(3(1 - 2 nu)) (J > 0). "
                         "`neohookean` = `neohookean_stable` on every element (hex8 used Bonet & Wood's "
                         "law under this name before; name it to keep that). A law defined for J > 0 "
                         "only stops the run at an inverted element. Every neo-Hookean law projects the "
                         "tet tangent to PSD in dynamic steps; static Newton uses the exact tangent "
                         "wherever it is positive definite.")
          .def("stvk"),
      Field::number("rayleigh_alpha", "1/s", "Mass-proportional Rayleigh damping.").at_least(0).def(0),
      Field::number("rayleigh_beta", "s", "Stiffness-proportional Rayleigh damping.").at_least(0).def(0),
  });
}

Field analysis() {
  return Field::enumeration("analysis", {"dynamic", "static"},
                            "`dynamic`: the implicit integrator in time; `static`: load stepping with "
                            "Newton-Raphson (`static` block, solid-only scenes), one output frame and one "
                            "probes.csv row per load step (time = load factor); gravity is not applied "
                            "(give a `body_force`).").def("dynamic");
}

Field model() {
  return Field::object("model", "Discretisation of the solid.", {
      Field::enumeration("type", {"tet_fem", "hex8"},
                         "`tet_fem`: the solid's tets of the meshed complex; `hex8`: Total Lagrangian "
                         "hexahedra, a structured block of a `box` geometry or the hexes of a `volume_mesh` "
                         "file, placed by `placement` (any rotation).").def("tet_fem"),
  }).tagged_by("type")
    .variant("tet_fem", {analysis()})
    .variant("hex8", {Field::integer("nx", "Cells along the box's x edge (box geometry; a volume_mesh "
                                           "brings its own cells).").at_least(1).def(8),
                      Field::integer("ny", "Cells along the box's y edge (box geometry).").at_least(1).def(2),
                      Field::integer("nz", "Cells along the box's z edge (box geometry).").at_least(1).def(2),
                      Field::enumeration("formulation", {"enhanced", "standard"},
                                         "`enhanced`: 9 incompatible modes on the displacement gradient per "
                                         "hex, condensed in the element (Taylor, Beresford & Wilson 1976; "
                                         "Simo & Armero 1992), which remove the shear locking in bending; "
                                         "`standard`: the fully integrated trilinear hex (as CalculiX's "
                                         "C3D8).").def("enhanced"),
                      analysis()});
}

Field integrator() {
  return Field::object("integrator", "Time integration of a deforming solid (solid-only runs).", {
      Field::enumeration("scheme", {"chentanez", "trapezoidal"},
                         "`chentanez`: Newmark beta = 1/2, gamma = 1 as in the paper's appendix (eq. 18; "
                         "slightly dissipative); `trapezoidal`: beta = 1/4, gamma = 1/2 (energy "
                         "conserving for linear models, can blow up for stiff nonlinear bodies).")
          .def("chentanez"),
      Field::enumeration("linear_solver", {"cholmod", "cg", "cg_ic"},
                         "Sparse SPD solver: CHOLMOD Cholesky, CG + Jacobi, or CG + incomplete Cholesky.")
          .def("cholmod"),
  });
}

Field static_solver() {
  return Field::object("static", "Load stepping of a solid with `analysis: static` (`tet_fem` or `hex8`).", {
      Field::integer("load_steps", "Equal load increments up to load factor 1.").at_least(1).def(10),
      Field::integer("max_iterations", "Newton iterations per load step before the step is halved.")
          .at_least(1).def(30),
      Field::number("residual_tolerance", "", "Relative residual |R| / max(|lambda F_ext|, |F_int|).")
          .greater(0).def(1e-9),
      Field::number("increment_tolerance", "", "Relative increment |du| / |u|.").greater(0).def(1e-8),
      Field::integer("max_step_cuts", "Successive halvings of one load increment before giving up.")
          .at_least(0).def(8),
      Field::enumeration("linear_solver", {"cholmod", "cg"}, "Newton solves: CHOLMOD or Jacobi CG.")
          .def("cholmod"),
  });
}

Field boundary_condition() {
  return Field::object("", "", {
      Field::enumeration("type", {"fixed", "displacement", "nodal_force", "traction", "moment_rotation",
                                  "moment_traction", "body_force", "pressure"},
                         "`fixed`: `components` held at 0; `displacement`: `value` [m] on `components` "
                         "(reached at load factor 1); `nodal_force`: `value` [N] on every node; "
                         "`traction`: dead `value` [Pa] on the boundary faces in the box; "
                         "`moment_rotation`: the nodes turn rigidly by `angle` [rad] about `axis` "
                         "through `center`, free translation (a pure end couple); `moment_traction`: "
                         "dead linear traction with couple `moment` [N m] about `axis`; `body_force`: "
                         "dead `value` [N/m^3] per reference volume on the nodes in the box (nodal share "
                         "m_a / density; a box around the whole body loads all of it); `pressure`: "
                         "follower `pressure` [Pa] on the boundary faces in the box, along the deformed "
                         "inward normal (positive pushes in).").req(),
      box("box", "Region (world coordinates [m]) selecting the nodes or boundary faces.").req(),
      Field::string("components", "Subset of \"xyz\" for `fixed` and `displacement`.").def("xyz"),
      Field::vector("value", 3, "m, N, Pa or N/m^3",
                    "Displacement [m], nodal force [N], traction [Pa] or body force [N/m^3].")
          .def({0, 0, 0}),
      Field::vector("axis", 3, "", "Rotation / moment axis (normalised internally).").def({0, 0, 1}),
      Field::vector("center", 3, "m", "A point on the rotation axis.").def({0, 0, 0}),
      Field::number("angle", "rad", "`moment_rotation`: rotation at load factor 1.").def(0),
      Field::number("moment", "N m", "`moment_traction`: couple at load factor 1.").def(0),
      Field::number("pressure", "Pa", "`pressure`: follower pressure at load factor 1 (nonzero).").def(0),
  }).check([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.at("type") == "pressure" && o.value("pressure", 0.0) == 0.0)
      issues.push_back({pointer_append(ptr, "pressure"), "expected a nonzero follower pressure [Pa] for type \"pressure\""});
    if (o.at("type") == "body_force" && o.value("value", Json::array({0, 0, 0})) == Json::array({0, 0, 0}))
      issues.push_back({pointer_append(ptr, "value"), "expected a nonzero body force [N/m^3] for type \"body_force\""});
  });
}

Field spring() {
  return Field::object("", "", {
      Field::string("name", "Name used in messages (default: the spring's index)."),
      box("region", "Box (world coordinates [m]): every solid node whose rest position lies inside is tied. "
                    "Give `region` or `point`."),
      Field::vector("point", 3, "m", "Tie only the solid node nearest to this point. Give `region` or `point`."),
      Field::vector("anchor", 3, "m", "Fixed anchor all selected nodes are tied to; omitted: each node is tied "
                                      "to its own rest position."),
      Field::number("stiffness", "N/m", "Total stiffness k, spread evenly over the selected nodes (each "
                                        "gets k/n), so a rigid shift d of the region feels -k d.").req().greater(0),
  }).check([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.contains("region") == o.contains("point"))
      issues.push_back({ptr, o.contains("region") ? "expected either `region` or `point`, got both"
                                                  : "expected `region` (a box) or `point`, got neither"});
  });
}

Field motion() {
  Field key = Field::object("", "", {
      Field::number("time", "s", "Time of the keyframe.").req().at_least(0),
      Field::vector("translation", 3, "m", "Translation at that time.").def({0, 0, 0}),
      Field::vector("rotation_deg", 3, "deg", "Euler XYZ rotation at that time.").def({0, 0, 0})});
  return Field::object("motion", "Prescribed (kinematic) motion; `none` lets the solid deform freely.", {
      Field::enumeration("type", {"none", "translation", "rotation", "path"},
                         "`translation`: constant velocity; `rotation`: constant angular velocity about "
                         "an axis; `path`: keyframes, interpolated linearly.").def("none"),
  }).tagged_by("type")
    .variant("none", {})
    .variant("translation", {Field::vector("velocity", 3, "m/s", "Constant velocity.").req()})
    .variant("rotation", {
        Field::vector("axis", 3, "", "Rotation axis (normalised internally).").req(),
        Field::vector("center", 3, "m", "A point on the axis, in world coordinates.").def({0, 0, 0}),
        Field::number("angular_velocity", "rad/s", "Angular speed (right-hand rule about `axis`).").req()})
    .variant("path", {Field::array("keyframes", "Keyframes in increasing time.", std::move(key)).items(2)})
    .check(nonzero("axis"))
    .check([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
      if (!o.contains("keyframes")) return;
      const auto& k = o["keyframes"];
      for (std::size_t i = 1; i < k.size(); ++i)
        if (!(k[i]["time"].get<double>() > k[i - 1]["time"].get<double>()))
          issues.push_back({fmt::format("{}/keyframes/{}/time", ptr, i),
                            "expected keyframe times in increasing order"});
    });
}

}  // namespace

Field solids() {
  Field solid = Field::object("", "", {
      Field::string("name", "Unique name, used in output file names and probes.").req(),
      geometry().req(),
      Field::object("placement", "Rigid placement of the rest shape: rotate, then translate. Region boxes "
                                 "(`fixed_regions`, `boundary_conditions`, spring regions) are world coordinates: "
                                 "they select the placed solid's nodes where they lie in the scene.", {
          Field::vector("translation", 3, "m", "Translation.").def({0, 0, 0}),
          Field::vector("rotation_deg", 3, "deg", "Euler XYZ rotation (about x, then y, then z).").def({0, 0, 0})}),
      model(),
      material().req(),
      Field::array("fixed_regions", "Boxes (world coordinates [m]); nodes inside are held in place in "
                   "`components` (all by default; a symmetry plane holds its normal component only).",
                   fixed_region()).def(Json::array()),
      Field::vector("initial_velocity", 3, "m/s", "Initial velocity of every node.").def({0, 0, 0}),
      Field::boolean("self_contact",
                     "`tet_fem` solids: the surface folds onto itself without passing through (a bunny's "
                     "ear against its head): node-to-surface contact between a surface node and the "
                     "triangles of the same solid that face it and lie farther than twice the film (or "
                     "half a surface edge) at rest (solid/contact/surface_contact.hpp). The film is "
                     "`coupling.contact_gap` in coupled scenes, 5% of the solid's mean surface edge in "
                     "solid-only scenes.")
          .def(false),
      Field::array("springs", "Linear springs tying a region of a `tet_fem` solid to fixed anchors "
                   "(coupled and solid runners).", spring()).def(Json::array()),
      motion(),
      integrator(),
      static_solver(),
      Field::array("boundary_conditions", "Conditions and loads by region of a deforming solid (`tet_fem` or "
                   "`hex8`, solid-only scenes; static and dynamic; in dynamic runs loads are applied at full value, "
                   "constant in time, and `displacement` and `moment_rotation` are not supported).",
                   boundary_condition()).def(Json::array()),
  });
  solid.checks.push_back([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.at("model").at("type") == "hex8" && o.at("geometry").at("type") != "box" &&
        o["geometry"]["type"] != "volume_mesh")
      issues.push_back({ptr + "/model/type", "expected \"tet_fem\": `hex8` needs a box or volume_mesh geometry"});
    const bool deforms = o.at("motion").at("type") == "none";
    const bool is_static = o["model"].value("analysis", "dynamic") == "static";
    if (!deforms && !o.at("boundary_conditions").empty())
      issues.push_back({ptr + "/boundary_conditions", "expected []: boundary conditions need a deforming solid "
                                                      "(motion \"none\")"});
    if (!deforms && is_static)
      issues.push_back({ptr + "/model/analysis", "expected \"dynamic\": a static analysis needs a deforming solid "
                                                 "(motion \"none\")"});
    if (o.at("model").at("type") == "hex8" && !o.at("springs").empty())
      issues.push_back({ptr + "/springs", "expected []: springs need model `tet_fem`"});
    if (is_static && !o.at("springs").empty())
      issues.push_back({ptr + "/springs", "expected []: springs are not part of a static analysis (use a `fixed` "
                                          "or `displacement` boundary condition)"});
    // The dynamic runners prescribe no motion; the dynamic hex runner holds whole nodes only.
    if (!is_static) {
      const bool hex8 = o.at("model").at("type") == "hex8";
      const auto& bcs = o.at("boundary_conditions");
      for (std::size_t j = 0; j < bcs.size(); ++j) {
        const auto type = bcs[j].at("type").get<std::string>();
        if (type == "displacement" || type == "moment_rotation")
          issues.push_back({fmt::format("{}/boundary_conditions/{}/type", ptr, j),
                            fmt::format("\"{}\" needs /model/analysis \"static\" (the dynamic runner prescribes no "
                                        "motion)", type)});
        else if (hex8 && type == "fixed" && bcs[j].at("components") != "xyz")
          issues.push_back({fmt::format("{}/boundary_conditions/{}/components", ptr, j),
                            "fixing single components needs /model/analysis \"static\"; dynamic runs fix whole nodes "
                            "(\"xyz\")"});
      }
      const auto& fixed = o.at("fixed_regions");
      for (std::size_t j = 0; j < fixed.size() && hex8; ++j)
        if (fixed[j].at("components").size() != 3)
          issues.push_back({fmt::format("{}/fixed_regions/{}/components", ptr, j),
                            "fixing single components of a hex8 solid needs /model/analysis \"static\"; dynamic "
                            "hex8 runs fix whole nodes ([\"x\", \"y\", \"z\"])"});
    }
    // Driven regions (fixed_regions[].velocity) belong to dynamic tet_fem solids.
    if (o.at("model").at("type") == "hex8" || is_static) {
      const auto& fixed = o.at("fixed_regions");
      for (std::size_t j = 0; j < fixed.size(); ++j)
        if (fixed[j].contains("velocity") && fixed[j]["velocity"] != Json::array({0, 0, 0}))
          issues.push_back({fmt::format("{}/fixed_regions/{}/velocity", ptr, j),
                            is_static ? "expected [0, 0, 0]: a static analysis has no time; prescribe a "
                                        "`displacement` boundary condition"
                                      : "a prescribed velocity is for tet_fem solids; a hex8 solid takes a prescribed "
                                        "motion as a `displacement` boundary condition (static analysis)"});
    }
  });
  return Field::array("solids", "Deformable or kinematic solids.", std::move(solid)).def(Json::array());
}

}  // namespace tetfsi::scene::blocks
