#include "apps/run/hex_geometry.hpp"

#include <limits>

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/solid_geometry.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/hex_volume_mesh.hpp"
#include "solid/hex/block_mesh.hpp"

namespace tetfsi::run {

mesh::HexMesh hex_mesh_of(const scene::Json& solid, std::vector<std::string>& warnings) {
  const auto& g = solid.at("geometry");
  const auto name = solid.at("name").get<std::string>();
  mesh::Placement placement = placement_of(solid);
  try {
    if (g.at("type") == "volume_mesh") {
      placement.unit_scale = g.at("unit_scale").get<double>();
      return mesh::import_hex_volume_mesh(g.at("file").get<std::string>(), placement, warnings);
    }
    const Eigen::Vector3d half = vec3(g.at("size")) / 2;
    const auto& m = solid.at("model");
    mesh::HexMesh hm = solid::hex::block_mesh(-half, half, m.at("nx").get<int>(), m.at("ny").get<int>(), m.at("nz").get<int>());
    mesh::apply_placement(hm.vertices, placement);
    return hm;
  } catch (const mesh::MeshError& e) {
    throw InputError(fmt::format("solid '{}': {}", name, e.what()));
  } catch (const std::invalid_argument& e) {  // block_mesh: counts or sizes the schema already bounds
    throw InputError(fmt::format("solid '{}': {}", name, e.what()));
  }
}

mesh::SurfaceMesh hex_boundary_surface(const mesh::HexMesh& hm) {
  mesh::SurfaceMesh s;
  const Eigen::Vector3d big = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  for (const auto& q : solid::hex::boundary_faces_in_box(hm, -big, big, 0.0)) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  s.vertices = hm.vertices;
  return s;
}

std::vector<std::pair<std::string, std::string>> empty_hex_regions(const scene::Json& solid, const mesh::HexMesh& hm,
                                                                   const std::string& ptr) {
  Eigen::Vector3d lo = hm.vertices.at(0), hi = lo;
  for (const auto& v : hm.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double tol = 1e-9 * (hi - lo).norm();
  const std::string where =
      fmt::format("the placed mesh of solid '{}' (bounding box [{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m); "
                  "boxes are world coordinates, after /placement", solid.at("name").get<std::string>(), lo.x(), lo.y(),
                  lo.z(), hi.x(), hi.y(), hi.z());
  std::vector<std::pair<std::string, std::string>> out;
  const auto& fixed = solid.at("fixed_regions");
  for (std::size_t j = 0; j < fixed.size(); ++j)
    if (solid::hex::nodes_in_box(hm, vec3(fixed[j].at("lo")), vec3(fixed[j].at("hi")), tol).empty())
      out.emplace_back(fmt::format("{}/fixed_regions/{}", ptr, j), "the box holds no node of " + where);
  const auto& bcs = solid.at("boundary_conditions");
  for (std::size_t j = 0; j < bcs.size(); ++j) {
    const Eigen::Vector3d a = vec3(bcs[j].at("box").at("lo")), b = vec3(bcs[j].at("box").at("hi"));
    const auto type = bcs[j].at("type").get<std::string>();
    const std::string key = fmt::format("{}/boundary_conditions/{}/box", ptr, j);
    if (solid::hex::nodes_in_box(hm, a, b, tol).empty())
      out.emplace_back(key, "the box holds no node of " + where);
    else if ((type == "traction" || type == "moment_traction") && solid::hex::boundary_faces_in_box(hm, a, b, tol).empty())
      out.emplace_back(key, fmt::format("a \"{}\" box must hold a whole boundary face (its 4 nodes) of {}", type, where));
  }
  return out;
}

}  // namespace tetfsi::run
