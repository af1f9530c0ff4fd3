#include <fmt/format.h>

#include "apps/scene/blocks/blocks.hpp"
#include "apps/scene/scene.hpp"

namespace tetfsi::scene::blocks {

Field obstacles() {
  Field plane = Field::object("", "", {
      Field::vector("point", 3, "m", "A point on the plane.").req(),
      Field::vector("normal", 3, "", "Normal pointing into the free side.").req()});
  plane.checks.push_back(nonzero("normal"));
  return Field::object("obstacles", "Static obstacles that solids collide with.", {
      Field::array("planes", "Half-spaces.", std::move(plane)).def(Json::array()),
      Field::array("boxes", "Solid boxes.", box("", "")).def(Json::array()),
      Field::number("friction", "", "Coulomb friction coefficient.").at_least(0).def(0),
  });
}

Field emitters() {
  Field shape = Field::object("shape", "Source volume: the fluid tets whose centroid lies inside (a sphere acts on its bounding box in the fluid runner).", {
      Field::enumeration("type", {"box", "sphere"}, "Shape of the source.").req()})
      .tagged_by("type")
      .variant("box", {Field::vector("lo", 3, "m", "Lower corner.").req(),
                       Field::vector("hi", 3, "m", "Upper corner.").req()})
      .variant("sphere", {Field::vector("center", 3, "m", "Centre.").req(),
                          Field::number("radius", "m", "Radius.").req().greater(0)})
      .check(lo_below_hi());
  Field emitter = Field::object("", "", {
      std::move(shape).req(),
      Field::vector("velocity", 3, "m/s",
                    "Fluid velocity imposed inside the source (not imposed if [0, 0, 0]).").def({0, 0, 0}),
      Field::number("smoke_density", "", "Smoke concentration set inside the source.").at_least(0).def(1),
      Field::number("temperature", "K", "Temperature set inside the source.").greater(0).def(373.15),
      Field::number("start_time", "s", "Time the source switches on.").at_least(0).def(0),
      Field::number("end_time", "s", "Time the source switches off; absent: never.").greater(0),
  }).check(start_before_end());
  return Field::array("emitters",
                      "Smoke or liquid sources. With a free-surface liquid (fluid.fill `regions`) the source "
                      "keeps its box full of liquid moving at `velocity` while it is on (a nozzle; a sphere acts "
                      "on its bounding box); the liquid it adds is added to the volume the run keeps.",
                      std::move(emitter))
      .def(Json::array());
}

Field probes() {
  Field probe = Field::object("", "", {
      Field::string("name", "Column name in probes.csv.").req(),
      Field::enumeration("kind", {"point_displacement", "solid_volume", "total_energy",
                                  "membrane_point", "membrane_radius", "membrane_volume", "particle_point",
                                  "body_energy", "fluid_point", "fluid_kinetic_energy", "fluid_volume", "fluid_force",
                                  "contact_force"},
                         "`point_displacement`: displacement [m] of the solid's material point nearest "
                         "to `point`; `solid_volume`: volume [m^3] of a solid; `total_energy`: kinetic "
                         "+ elastic + gravitational energy [J] of everything (mpm scenes: the stored energy of "
                         "particles and membrane). Scenes with an `mpm` block: `membrane_point`: a `quantity` of "
                         "the membrane node nearest to `point` at t = 0 (its position x, y, z [m] or displacement); "
                         "`membrane_radius`: smallest or largest node distance [m] from the axis through `center` "
                         "along `axis`; `membrane_volume`: volume [m^3] enclosed by a closed membrane (with "
                         "symmetry planes: the modelled part, the planes closing it); `particle_point`: a `quantity` "
                         "of the body's particle nearest to `point` at t = 0; `body_energy`: kinetic, internal "
                         "(fluids: E V0; solids and membrane: strain, + hourglass) or total energy [J] of a body or "
                         "of the membrane (by name). Fluid runner: "
                         "`fluid_point`: one fluid `quantity` at `point` (NaN outside the fluid); "
                         "`fluid_kinetic_energy`: 1/2 rho sum V |u|^2 of the fluid [J] (of the liquid part of each "
                         "tet for a free surface); `fluid_volume`: volume of the fluid [m^3]: the liquid's "
                         "for a free surface (fluid.fill `regions`), else the fluid mesh's; in the coupled "
                         "runner with the solids at their current position (the cavity volume when the "
                         "fluid fills only a shell's cavity). Fluid and coupled runners: `fluid_force`: the "
                         "fluid's force [N] on a solid in the last step (columns _x, _y, _z): the pressure part "
                         "(int p n dA over its interface; coupled: the sum of J p over its nodes, Chentanez et "
                         "al. 2006 sec. 3.4) and the viscous part (the no-slip reaction of the viscous step, "
                         "fluid/README.md \"Viscosity\"). Coupled and solid runners: `contact_force`: the "
                         "contact force [N] on a solid in the last step (columns _x, _y, _z), from the container's "
                         "walls, the obstacles and the other solids: the sum of the normal constraint forces of "
                         "its contact nodes (a body at rest on the floor: its weight less the fluid's buoyancy).").req()})
      .tagged_by("kind")
      .variant("point_displacement", {
          Field::string("solid", "Name of the solid.").req(),
          Field::vector("point", 3, "m", "Rest position of the tracked point.").req()})
      .variant("solid_volume", {Field::string("solid", "Name of the solid.").req()})
      .variant("contact_force", {Field::string("solid", "Name of the solid.").req()})
      .variant("fluid_force", {Field::string("solid", "Name of the solid.").req(),
                               Field::enumeration("part", {"total", "pressure", "viscous"},
                                                  "`pressure`: the pressure force; `viscous`: the viscous "
                                                  "(no-slip) traction, 0 for an inviscid fluid; `total`: both "
                                                  "(drag and lift are its components).")
                                   .def("total")})
      .variant("total_energy", {})
      .variant("fluid_point", {
          Field::vector("point", 3, "m", "Where to sample (world coordinates).").req(),
          Field::enumeration("quantity", {"pressure", "smoke", "temperature", "speed", "velocity_x",
                                          "velocity_y", "velocity_z"},
                             "`pressure` [Pa] (linear in the tet), `smoke` [-], `temperature` [K], "
                             "`speed` and velocity components [m/s] (the tet's value).").req()})
      .variant("fluid_kinetic_energy", {})
      .variant("fluid_volume", {});
  const std::vector<std::string> point_quantities = {"x", "y", "z", "displacement_x", "displacement_y",
                                                     "displacement_z", "displacement"};
  const std::string quantity_doc = "`x`, `y`, `z`: position [m]; `displacement_x` ... `_z`: displacement component, "
                                   "`displacement`: its length [m] (from the position at t = 0).";
  probe.variants["membrane_point"] = {
      Field::vector("point", 3, "m", "The node nearest to this point at t = 0 is tracked.").req(),
      Field::enumeration("quantity", point_quantities, quantity_doc).req()};
  probe.variants["membrane_radius"] = {
      Field::vector("center", 3, "m", "A point on the axis.").def({0, 0, 0}),
      Field::vector("axis", 3, "", "Direction of the axis.").def({0, 0, 1}),
      Field::enumeration("statistic", {"min", "max"}, "Smallest or largest distance over the nodes.").req()};
  probe.variants["membrane_volume"] = {};
  probe.variants["particle_point"] = {
      Field::string("body", "Name of the particle body (/mpm/bodies).").req(),
      Field::vector("point", 3, "m", "The body's particle nearest to this point at t = 0 is tracked.").req(),
      Field::enumeration("quantity", point_quantities, quantity_doc).req()};
  probe.variants["body_energy"] = {
      Field::string("body", "Name of a particle body or of the membrane.").req(),
      Field::enumeration("energy", {"kinetic", "internal", "total"}, "Which energy.").def("total")};
  return Field::array("probes", "Quantities written to probes.csv every step.", std::move(probe))
      .def(Json::array());
}

/// export.liquid_surface: how surfaces/liquid_NNNNN.ply is made (fluid/io/render_surface.hpp).
Field liquid_surface() {
  Field f = Field::object(
      "liquid_surface",
      "The liquid's surface written to surfaces/liquid_NNNNN.ply (free-surface liquids, fluid.fill `regions`), "
      "with per-vertex velocity [m/s] (the fluid's node-averaged velocity interpolated in the tet holding the "
      "vertex).",
      {Field::enumeration("type", {"smooth", "tets"},
                          "`smooth`: the level set sampled on voxels of `voxel_size`, smoothed by the heat "
                          "equation for a time smoothing^2 / 2 (a Gaussian of standard deviation `smoothing`; "
                          "mean-curvature flow of the surface) inside the fluid only, the walls and solids not "
                          "crossed, cut off at them so that the liquid ends on them with a sharp edge, meshed "
                          "(OpenVDB volumeToMesh: closed, watertight), and its iso-value shifted by the one "
                          "constant that makes it enclose the liquid's volume (to 1e-4); `tets`: the marching-tets "
                          "zero set of the nodal level set plus the wet parts of the fluid's boundary faces "
                          "(closed, the liquid's volume exactly, facets and kinks at the scale of the tets).")
           .def("smooth"),
       Field::number("voxel_size", "m",
                     "`smooth`: voxel edge of the meshing (the surface's triangles are about this long); absent: a "
                     "quarter of `smoothing`, or with `smoothing` 0 a quarter of the default smoothing. Kept for "
                     "the run.")
           .greater(0),
       Field::number("smoothing", "m",
                     "`smooth`: standard deviation of the Gaussian: wrinkles of wavelength 2 x smoothing keep 0.7% "
                     "of their height, 4 x 29%, 10 x 82%; a plane is unchanged; drops and sheets much thinner "
                     "than it shrink (the iso shift gives their volume back to the whole liquid). 0: none (the "
                     "level set resampled and meshed). At most 10 voxels. Absent: the mean edge length of the "
                     "finest tets the surface cuts at the first frame (10th percentile of the cut tets), kept "
                     "for the run.")
           .at_least(0)});
  f.checks.push_back([](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (o.value("type", "smooth") == "tets") {
      for (const char* key : {"voxel_size", "smoothing"})
        if (o.contains(key))
          issues.push_back({pointer_append(ptr, key), fmt::format("\"{}\" belongs to type \"smooth\" only", key)});
      return;
    }
    if (o.contains("voxel_size") && o.contains("smoothing") &&
        !(o["smoothing"].get<double>() <= kMaxSmoothingVoxels * o["voxel_size"].get<double>()))
      issues.push_back({pointer_append(ptr, "smoothing"),
                        fmt::format("{:g} m is more than {:g} voxels of {:g} m: raise voxel_size or lower smoothing",
                                    o["smoothing"].get<double>(), kMaxSmoothingVoxels, o["voxel_size"].get<double>())});
  });
  return f;
}

Field output() {
  return Field::object("export", "What is written to the output folder.", {
      Field::boolean("vtu", "Write a .pvd collection with one .vtu per frame per object (ParaView).").def(true),
      Field::enumeration("compression", {"zlib", "none"},
                         "How .vtu data arrays are stored: `zlib` compresses them (VTK's vtkZLibDataCompressor "
                         "blocks, raw appended data; ParaView and VTK read it); `none` writes them uncompressed "
                         "as inline base64.")
          .def("zlib"),
      Field::enumeration("precision", {"float32", "float64"},
                         "Type of the .vtu point and cell fields (pressure, velocity, smoke, displacement, stress, "
                         "...): `float32` rounds each value to the nearest float (relative error <= 6e-8, about "
                         "half the bytes); `float64` stores the computed doubles exactly. Points (Float64) and "
                         "cells (Int64) are stored exactly either way.")
          .def("float32"),
      Field::enumeration("surfaces", {"none", "ply", "obj"},
                         "Per-frame solid surfaces for Blender/Houdini (PLY carries per-vertex velocity).")
          .def("ply"),
      Field::enumeration("up_axis", {"y", "z"},
                         "Up axis of the exported files. The scenes are Y-up (`y`: files in scene coordinates); "
                         "`z` turns every exported position and vector (.vtu points and 3-component fields, "
                         "surface positions and velocities) by +90 degrees about x, (x, y, z) -> (x, -z, y), so "
                         "that scene +y is +z (Blender's up). stats.csv and probes.csv stay in scene coordinates.")
          .def("y"),
      Field::enumeration("volumes", {"none", "vdb"},
                         "Per-frame fluid volumes for renderers (tet-mesh fluid runners): `vdb` writes "
                         "volumes/fluid_NNNNN.vdb (OpenVDB) with float grids `density` (smoke) and `temperature` [K] "
                         "and a Vec3f grid `velocity` [m/s], the node fields interpolated linearly in the tets at the "
                         "voxel centres inside the fluid (background 0 outside), and for a free-surface liquid the "
                         "level-set grid `surface` (signed distance [m] to the liquid surface, narrow band of 3 "
                         "voxels). Turned as `up_axis` says.")
          .def("none"),
      Field::number("voxel_size", "m",
                    "Voxel edge of the volumes (voxel centres at integer multiples of it); absent: half the "
                    "fluid mesh's mean edge length at the first frame.")
          .greater(0),
      liquid_surface(),
      Field::integer("every_n_frames", "Write every n-th frame only.").at_least(1).def(1),
      Field::integer("checkpoint_every",
                     "Write a checkpoint (the whole state: fluid mesh and fields, solids, liquid surface, MPM "
                     "particles and membrane, step, time-step state) after every n-th frame, and at the end when it "
                     "is a frame, to checkpoint/checkpoint_NNNNN.bin (atomically; the newest two are kept), so that "
                     "`tetfsi run SCENE --out DIR --resume` continues a stopped or killed run, bit for bit as if "
                     "uninterrupted. 0: none (a checkpoint is a full state, tens of MB on large meshes). The "
                     "coupled, fluid, solid (dynamic) and mpm runners write them; other scenes must leave it 0.")
          .at_least(0).def(0),
      Field::number("max_output_gb", "GB",
                    "Largest estimated size of the output folder (frames x frame size + stats rows); a scene "
                    "that would write more is refused before it starts.").greater(0).def(20),
  });
}

}  // namespace tetfsi::scene::blocks
