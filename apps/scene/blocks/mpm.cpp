/// @file mpm.cpp
/// The `mpm` block: particle bodies (MPM, Lian, Liu & Zhang 2014, section 3) in grid contact
/// (section 5) with a Belytschko-Tsay membrane (section 4) on a regular background grid. The
/// schema checks types and ranges; apps/mpm/setup.cpp builds the problem and reports what only the
/// geometry shows (files, particles outside the grid, empty regions), for `validate` and `run` alike.
#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {
namespace {

std::vector<std::string> face_names() { return {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"}; }

Field grid() {
  std::vector<Field> faces;
  for (const auto& f : face_names())
    faces.push_back(Field::enumeration(f, {"free", "slip", "fixed"}, "Condition on the grid nodes of this face.").def("free"));
  return Field::object("grid", "The background grid: a box of cubic cells. Particles must lie inside it; the membrane "
                               "nodes too.", {
      Field::vector("lo", 3, "m", "Lower corner.").req(),
      Field::vector("hi", 3, "m", "Upper corner (rounded up to whole cells).").req(),
      Field::number("cell", "m", "Cell size h (the contact's distance unit, eq. 21's length).").req().greater(0),
      Field::object("faces", "Face conditions on the grid momentum (section 6, steps 2b and 2e): `free`; `slip`: normal "
                             "component zero (a symmetry plane or a frictionless wall); `fixed`: all components zero.",
                    std::move(faces)),
      Field::enumeration("plane_motion", {"none", "xy", "yz", "xz"},
                         "Motion held in this plane on every node (plane strain; the grid is then usually one or two "
                         "cells thick across it).").def("none"),
  }).check(lo_below_hi());
}

Field initial_pressure() {
  return Field::number("pressure", "Pa", "Fluids: initial pressure p; the internal energy per reference volume E "
                                         "follows from the equation of state, p = (gamma - 1) (rho / rho0) E (ideal gas, "
                                         "eq. 67) or eq. (66). Give this or `internal_energy` (neither: E = 0).");
}

/// Like blocks::nonzero, for a key that is a vector in some variants only.
Check nonzero_vector(std::string key) {
  return [key, inner = nonzero(key)](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.contains(key) && o[key].is_array()) inner(o, ptr, issues);
  };
}

Field body_shape() {
  return Field::object("shape", "Region filled with particles on a lattice of `spacing` (centres lo + (i + 1/2) "
                                "spacing in the shape's bounding box, kept if inside).", {
      Field::enumeration("type", {"box", "sphere", "cylinder", "file"},
                         "`box`: lo to hi; `sphere`; `cylinder`: from `base` along `axis` (its length is the height); "
                         "`file`: the inside of a closed surface (OBJ, PLY, STL, glTF, FBX, OFF; checked closed, "
                         "manifold, outward, not self-intersecting).").req()})
      .tagged_by("type")
      .variant("box", {Field::vector("lo", 3, "m", "Lower corner.").req(), Field::vector("hi", 3, "m", "Upper corner.").req()})
      .variant("sphere", {Field::vector("center", 3, "m", "Centre.").req(),
                          Field::number("radius", "m", "Radius.").req().greater(0)})
      .variant("cylinder", {Field::vector("base", 3, "m", "Centre of one end.").req(),
                            Field::vector("axis", 3, "m", "From that end to the other.").req(),
                            Field::number("radius", "m", "Radius.").req().greater(0)})
      .variant("file", {Field::file("file", "Closed surface file, relative to the scene file's folder.").req(),
                        Field::number("unit_scale", "m/unit", "Metres per file unit.").greater(0).def(1.0),
                        Field::vector("rotation_deg", 3, "deg", "Euler XYZ rotation (about x, then y, then z).").def({0, 0, 0}),
                        Field::vector("translation", 3, "m", "Translation after the rotation.").def({0, 0, 0})})
      .check(lo_below_hi())
      .check(nonzero_vector("axis"));
}

Field body_material() {
  return Field::object("material", "Constitutive model of the particles (section 3.3).", {
      Field::enumeration("type", {"linear_elastic", "ideal_gas", "mie_gruneisen"},
                         "`linear_elastic`: hypo-elastic solid, Jaumann rate (eqs. 22, 25); `ideal_gas`: p = (gamma - 1) "
                         "(rho / rho0) E (eq. 67); `mie_gruneisen`: Hugoniot pressure + gamma0 E in compression, 0 in "
                         "tension (eq. 66). The fluids add a shear viscosity (eq. 26).").req(),
      Field::number("density", "kg/m^3", "Reference density rho0.").req().greater(0)})
      .tagged_by("type")
      .variant("linear_elastic", {youngs_modulus("Young's modulus E."),
                                  Field::number("poissons_ratio", "", "Poisson's ratio nu.").req().greater(-1).less(0.5)})
      .variant("ideal_gas", {Field::number("gamma", "", "Ratio of specific heats.").greater(1).at_most(5).def(1.4),
                             Field::number("viscosity", "Pa s", "Shear viscosity mu.").at_least(0).def(0)})
      .variant("mie_gruneisen", {Field::number("c0", "m/s", "Bulk sound speed (Table 1: water 1647).").req().greater(0),
                                 Field::number("s", "", "Slope of the shock-particle velocity line (water 1.921).")
                                     .req().at_least(0).less(10),
                                 Field::number("gamma0", "", "Grueneisen gamma_0 (water 0.1).").req().at_least(0).at_most(5),
                                 Field::number("viscosity", "Pa s", "Shear viscosity mu.").at_least(0).def(0)});
}

Field body() {
  return Field::object("", "", {
      Field::string("name", "Unique name (probes, sources).").req(),
      body_shape().req(),
      Field::number("spacing", "m", "Particle lattice spacing, between cell / 6 and the cell (paper: cell / 2).").req().greater(0),
      body_material().req(),
      Field::vector("velocity", 3, "m/s", "Initial velocity.").def({0, 0, 0}),
      Field::number("density", "kg/m^3", "Initial density (absent: the material's reference density); mass = density "
                                         "x spacing^3 per particle.").greater(0),
      initial_pressure().at_least(0),
      Field::number("internal_energy", "J/m^3", "Fluids: initial internal energy per reference volume E (the paper's "
                                                "convention; Table 2: E0 = 25 for p0 = 10).").at_least(0),
  });
}

Field membrane_shape() {
  return Field::object("shape", "Membrane surface, meshed into quads of about `element_size`.", {
      Field::enumeration("type", {"rectangle", "disc", "cylinder", "box_tube", "cushion", "sphere", "file"},
                         "`rectangle`: origin + s u + t v (normal u x v); `disc`; `cylinder`: open tube from `base` "
                         "along `axis`; `box_tube`: open tube of rectangular section; `cushion`: closed box surface "
                         "(an airbag: thin along one axis); `sphere`: closed (cube mapped onto the sphere); `file`: a "
                         "triangle surface, each triangle split into three quads at its edge midpoints and centroid "
                         "(the element is a quad; open or closed, consistently oriented).").req()})
      .tagged_by("type")
      .variant("rectangle", {Field::vector("origin", 3, "m", "A corner.").req(),
                             Field::vector("u", 3, "m", "First edge.").req(),
                             Field::vector("v", 3, "m", "Second edge.").req()})
      .variant("disc", {Field::vector("center", 3, "m", "Centre.").req(),
                        Field::vector("normal", 3, "", "Normal.").req(),
                        Field::number("radius", "m", "Radius.").req().greater(0)})
      .variant("cylinder", {Field::vector("base", 3, "m", "Centre of one end.").req(),
                            Field::vector("axis", 3, "m", "From that end to the other.").req(),
                            Field::number("radius", "m", "Radius.").req().greater(0)})
      .variant("box_tube", {Field::vector("base", 3, "m", "Centre of the first section.").req(),
                            Field::enumeration("axis", {"x", "y", "z"}, "Axis of the tube.").req(),
                            Field::vector("half_widths", 2, "m", "Half widths along the next two axes (cyclic: y, z "
                                                                 "for x; z, x for y; x, y for z).").req().greater(0),
                            Field::number("length", "m", "Length along the axis.").req().greater(0)})
      .variant("cushion", {Field::vector("center", 3, "m", "Centre.").req(),
                           Field::vector("size", 3, "m", "Edge lengths.").req().greater(0)})
      .variant("sphere", {Field::vector("center", 3, "m", "Centre.").req(),
                          Field::number("radius", "m", "Radius.").req().greater(0)})
      .variant("file", {Field::file("file", "Surface file, relative to the scene file's folder.").req(),
                        Field::number("unit_scale", "m/unit", "Metres per file unit.").greater(0).def(1.0),
                        Field::vector("rotation_deg", 3, "deg", "Euler XYZ rotation (about x, then y, then z).").def({0, 0, 0}),
                        Field::vector("translation", 3, "m", "Translation after the rotation.").def({0, 0, 0})})
      .check(nonzero_vector("normal"))
      .check(nonzero_vector("axis"));
}

Field fixed_region() {
  Field region = Field::object("region", "Nodes held (a node is in a region within 1e-9 of the grid diagonal).", {
      Field::enumeration("type", {"all", "boundary", "box", "plane"},
                         "`all`; `boundary`: the free edges (edges of one element, not in a symmetry plane); `box`: "
                         "nodes in lo..hi; `plane`: nodes on the plane x_axis = position.").req()})
      .tagged_by("type")
      .variant("all", {})
      .variant("boundary", {})
      .variant("box", {Field::vector("lo", 3, "m", "Lower corner.").req(), Field::vector("hi", 3, "m", "Upper corner.").req()})
      .variant("plane", {Field::enumeration("axis", {"x", "y", "z"}, "Normal axis.").req(),
                         Field::number("position", "m", "Coordinate of the plane.").req()})
      .check(lo_below_hi());
  return Field::object("", "", {
      std::move(region).req(),
      Field::enumeration("components", {"x", "y", "z", "xy", "xz", "yz", "xyz"},
                         "Velocity components held at zero.").def("xyz"),
  });
}

Field membrane() {
  return Field::object("membrane", "The membrane (Belytschko-Tsay quads, co-rotational, one-point quadrature with "
                                   "Flanagan-Belytschko hourglass control, section 4).", {
      Field::string("name", "Name (body_energy probes).").def("membrane"),
      membrane_shape().req(),
      Field::number("element_size", "m", "Target element edge length (grid cell or smaller, paper: the cell).").req().greater(0),
      Field::number("thickness", "m", "Thickness t (constant).").req().greater(0),
      Field::number("density", "kg/m^3", "Density.").req().greater(0),
      youngs_modulus("Young's modulus (plane stress)."),
      Field::number("poissons_ratio", "", "Poisson's ratio.").req().greater(-1).less(0.5),
      Field::number("hourglass", "", "Flanagan-Belytschko stiffness coefficient of the in-plane hourglass modes.")
          .at_least(0).at_most(1).def(0.1),
      Field::number("damping", "1/s", "Mass-proportional damping c: f -= c m v (dynamic relaxation; needs c dt < 2).")
          .at_least(0).def(0),
      Field::vector("velocity", 3, "m/s", "Initial velocity of every free node.").def({0, 0, 0}),
      Field::number("pressure", "Pa", "Uniform pressure on the membrane along the deformed element normal (a "
                                      "follower load, f = p S_e / 4 per node; the normal is u x v, outward for closed "
                                      "shapes).").def(0),
      Field::array("fixed", "Held nodes, per region and component.", fixed_region()).def(Json::array()),
  });
}

Field source() {
  return Field::object("", "", {
      Field::string("body", "Name of the fluid body whose material the inflow has (its spacing sets the particle size).").req(),
      box("region", "Inflow region: particles are placed in turn on the lattice sites of the body's spacing in it.").req(),
      Field::number("mass_rate", "kg/s", "Mass inflow rate (one particle of density x spacing^3 whenever that much is due).")
          .req().greater(0),
      Field::number("density", "kg/m^3", "Density of the inflowing gas (absent: the material's reference density).").greater(0),
      Field::number("pressure", "Pa", "Its pressure (or `internal_energy`; neither: E = 0).").at_least(0),
      Field::number("internal_energy", "J/m^3", "Its internal energy per reference volume.").at_least(0),
      Field::vector("velocity", 3, "m/s", "Its velocity.").def({0, 0, 0}),
      Field::number("start_time", "s", "Inflow starts.").at_least(0).def(0),
      Field::number("end_time", "s", "Inflow stops.").req().greater(0),
  }).check(start_before_end());
}

Field contact() {
  return Field::object("contact", "Grid contact between particles and membrane (section 5).", {
      Field::enumeration("mode", {"slip", "stick"},
                         "`slip`: Coulomb sliding (eqs. 56-58); `stick`: no relative tangential motion "
                         "(eq. 55).").def("slip"),
      Field::number("friction", "", "Coulomb coefficient mu of eq. (58) (slip mode).").at_least(0).def(0.0),
      Field::number("distance_factor", "",
                    "A contact found in momentum form (eq. 52) is kept only if the membrane is within "
                    "this many cells of the particles (the membrane is stopped at most that far from the "
                    "particle surface).")
          .greater(0).at_most(1).def(0.25),
  });
}

}  // namespace

Field mpm() {
  return Field::object("mpm",
                       "MPM particle bodies in contact with one Belytschko-Tsay membrane on a background grid "
                       "(Lian, Liu & Zhang 2014). Run by the `mpm` runner; the scene then has no `fluid` and no "
                       "`solids`. `simulation.gravity` acts on particles and membrane, `simulation.end_time` is "
                       "the end time, frames follow `simulation.frame_rate`; `simulation.cfl` is not used "
                       "(`mpm_cfl`, `membrane_cfl`). (The former `example` key is gone: the paper's examples are "
                       "the scene files data/scenes/gas_expansion.json, sphere_on_membrane.json, water_sphere.json "
                       "and membrane_on_sphere.json.)", {
      grid().req(),
      Field::array("bodies", "Particle bodies (one material each).", body()).items(1).req(),
      membrane().req(),
      Field::array("symmetry_planes", "Symmetry planes x_axis = position, each the grid's lower face on its axis: the "
                                      "model is the part x_axis >= position (bodies and membrane are cut to it), the "
                                      "grid face is `slip` and the membrane nodes on the plane keep zero normal velocity.",
                   Field::object("", "", {Field::enumeration("axis", {"x", "y", "z"}, "Normal axis.").req(),
                                          Field::number("position", "m", "Coordinate of the plane.").def(0)}))
          .def(Json::array()),
      Field::array("sources", "Gas inflow (airbag inflators): particles added in a region at a mass rate.", source())
          .def(Json::array()),
      contact(),
      Field::number("mpm_cfl", "", "Safety factor on the MPM critical step of eq. (21).").greater(0).at_most(1).def(0.5),
      Field::number("membrane_cfl", "", "Safety factor on the membrane critical step min(L_e / c) (eq. 48).")
          .greater(0).at_most(1).def(0.9),
      Field::integer("stats_rows_per_frame",
                     "Rows of stats.csv and probes.csv per output frame. Each row holds the exact state at "
                     "its time; the coupled steps between rows (often thousands: the explicit step is "
                     "limited by the critical step of section 4.4) are not written.")
          .at_least(1).at_most(1000).def(1),
  });
}

}  // namespace tetfsi::scene::blocks
