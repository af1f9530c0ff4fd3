#include "apps/run/scene_values.hpp"
#include "apps/run/solid_geometry.hpp"

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "apps/run/tet_tools.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_import.hpp"
#include "mesh/volume_mesh.hpp"

namespace tetfsi::run {

mesh::Placement placement_of(const scene::Json& solid) {
  mesh::Placement placement;
  placement.rotation_deg = vec3(solid.at("placement").at("rotation_deg"));
  placement.translation = vec3(solid.at("placement").at("translation"));
  return placement;
}

mesh::TetMesh volume_mesh_of(const scene::Json& solid, std::vector<std::string>& warnings) {
  const auto& g = solid.at("geometry");
  mesh::Placement placement = placement_of(solid);
  placement.unit_scale = g.at("unit_scale").get<double>();
  try {
    return mesh::import_volume_mesh(g.at("file").get<std::string>(), placement, warnings);
  } catch (const mesh::MeshError& e) {
    throw InputError(fmt::format("solid '{}': {}", solid.at("name").get<std::string>(), e.what()));
  }
}

mesh::SurfaceMesh surface_of(const scene::Json& solid, std::vector<std::string>& warnings, mesh::SurfaceMesh* cavity,
                             int* volume_tets) {
  const auto& g = solid.at("geometry");
  const auto type = g.at("type").get<std::string>();
  const auto name = solid.at("name").get<std::string>();
  if (type == "sphere_shell" && cavity == nullptr)
    throw InputError(fmt::format("solid '{}': a sphere_shell (a solid with a fluid cavity) is meshed only by the "
                                 "coupled runner (a fluid, every solid a deforming tet solid)", name));
  if (cavity != nullptr) *cavity = cavity_of(solid);
  mesh::Placement placement = placement_of(solid);
  try {
    mesh::SurfaceMesh s;
    std::string label = fmt::format("solid '{}'", name);
    if (type == "volume_mesh") {
      label += " (" + g.at("file").get<std::string>() + ", boundary of the tets)";
      const mesh::TetMesh tets = volume_mesh_of(solid, warnings);
      if (volume_tets != nullptr) *volume_tets = tets.num_tets();
      s = boundary_surface(tets);
    } else if (type == "mesh") {
      placement.unit_scale = g.at("unit_scale").get<double>();
      label += " (" + g.at("file").get<std::string>() + ")";
      s = mesh::import_surface(g.at("file").get<std::string>(), placement);
    } else {
      if (type == "box") s = mesh::make_box(vec3(g.at("size")));
      else if (type == "bowl")
        s = mesh::make_bowl(g.at("radius").get<double>(), g.at("thickness").get<double>(), g.at("segments").get<int>(),
                            g.at("rings").get<int>());
      else if (type == "cylinder") {
        s = mesh::make_cylinder(g.at("radius").get<double>(), g.at("length").get<double>(), g.at("segments").get<int>());
        for (auto& v : s.vertices) v = Eigen::Vector3d(v.x(), v.z(), -v.y());  // axis z -> y (a rotation: orientation kept)
      } else if (type == "sphere" || type == "sphere_shell")
        s = mesh::make_sphere(g.at("radius").get<double>(), g.at("subdivisions").get<int>());
      else  // sheet: size along x and z, thickness along y (a horizontal slab when y is up)
        s = mesh::make_box({g.at("size")[0].get<double>(), g.at("thickness").get<double>(), g.at("size")[1].get<double>()});
      mesh::apply_placement(s, placement);
    }
    for (auto& w : mesh::validate_surface(s, label)) warnings.push_back(std::move(w));
    return s;
  } catch (const mesh::MeshError& e) {
    throw InputError(e.what());
  }
}

mesh::SurfaceMesh placed_surface_file(const scene::Json& placed, const std::string& what,
                                      std::vector<std::string>& warnings) {
  const auto file = placed.at("file").get<std::string>();
  try {
    mesh::Placement placement;
    placement.unit_scale = placed.at("unit_scale").get<double>();
    placement.rotation_deg = vec3(placed.at("rotation_deg"));
    placement.translation = vec3(placed.at("translation"));
    auto s = mesh::import_surface(file, placement);
    for (auto& w : mesh::validate_surface(s, what + " (" + file + ")")) warnings.push_back(std::move(w));
    return s;
  } catch (const mesh::MeshError& e) {
    throw InputError(e.what());
  }
}

mesh::SurfaceMesh liquid_region_surface(const scene::Json& region, std::vector<std::string>& warnings) {
  return placed_surface_file(region, "liquid region", warnings);
}

mesh::SurfaceMesh import_checked(const std::string& file, double unit_scale, std::vector<std::string>& warnings) {
  try {
    mesh::Placement placement;
    placement.unit_scale = unit_scale;
    auto s = mesh::import_surface(file, placement);
    for (auto& w : mesh::validate_surface(s, file)) warnings.push_back(std::move(w));
    return s;
  } catch (const mesh::MeshError& e) {
    throw InputError(e.what());
  }
}

mesh::SurfaceMesh cavity_of(const scene::Json& solid) {
  const auto& g = solid.at("geometry");
  if (g.at("type") != "sphere_shell") return {};
  const mesh::Placement placement = placement_of(solid);
  try {
    mesh::SurfaceMesh c = mesh::make_sphere(g.at("radius").get<double>() - g.at("thickness").get<double>(),
                                            g.at("subdivisions").get<int>());
    mesh::apply_placement(c, placement);
    return c;
  } catch (const mesh::MeshError& e) {
    throw InputError(fmt::format("solid '{}' cavity: {}", solid.at("name").get<std::string>(), e.what()));
  }
}

}  // namespace tetfsi::run
