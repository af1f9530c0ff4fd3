#include "apps/run/container.hpp"

#include <algorithm>
#include <cmath>

#include "apps/run/scene_values.hpp"
#include "mesh/primitives.hpp"

namespace tetfsi::run {

mesh::SurfaceMesh container_surface(const scene::Json& domain) {
  if (!domain.contains("container")) return {};
  const auto& c = domain["container"];
  const auto type = c.at("type").get<std::string>();
  if (type == "box") return {};
  const Eigen::Vector3d center = vec3(c.at("center"));
  mesh::SurfaceMesh s;
  if (type == "sphere") {
    s = mesh::make_sphere(c.at("radius").get<double>(), c.at("subdivisions").get<int>());
  } else {
    s = mesh::make_cylinder(c.at("radius").get<double>(), c.at("length").get<double>(), c.at("segments").get<int>());
    const char axis = c.at("axis").get<std::string>()[0];
    // The cylinder is made along z; a cyclic permutation (a rotation) sends z to the axis.
    for (auto& v : s.vertices) {
      if (axis == 'x') v = Eigen::Vector3d(v.z(), v.x(), v.y());
      else if (axis == 'y') v = Eigen::Vector3d(v.y(), v.z(), v.x());
    }
  }
  for (auto& v : s.vertices) v += center;
  return s;
}

mesh::TetMesh mesh_container(const scene::Json& domain, const std::vector<mesh::SurfaceMesh>& solids,
                             const mesh::MeshSizing& sizing, const std::vector<mesh::SurfaceMesh>& cavities) {
  const mesh::SurfaceMesh container = container_surface(domain);
  if (container.vertices.empty())
    return mesh::build_complex(vec3(domain.at("lo")), vec3(domain.at("hi")), solids, sizing, cavities);
  return mesh::build_complex(container, solids, sizing, cavities);
}

std::vector<solid::PlaneObstacle> container_wall_planes(const scene::Json& domain, double gap) {
  std::vector<solid::PlaneObstacle> planes;
  const mesh::SurfaceMesh container = container_surface(domain);
  if (container.vertices.empty()) {
    const Eigen::Vector3d lo = vec3(domain.at("lo")), hi = vec3(domain.at("hi"));
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d n = Eigen::Vector3d::Unit(axis);
      planes.push_back({lo + gap * n, n});
      planes.push_back({hi - gap * n, -n});
    }
    return planes;
  }
  double size = 0;
  for (const auto& v : container.vertices) size = std::max(size, (v - container.vertices[0]).norm());
  for (const auto& t : container.triangles) {
    const Eigen::Vector3d& a = container.vertices[t[0]];
    const Eigen::Vector3d inward = -(container.vertices[t[1]] - a).cross(container.vertices[t[2]] - a).normalized();
    const bool known = std::any_of(planes.begin(), planes.end(), [&](const solid::PlaneObstacle& p) {
      return p.normal.dot(inward) > 1 - 1e-12 && std::abs((a - p.point).dot(p.normal) + gap) < 1e-12 * size;
    });
    if (!known) planes.push_back({a + gap * inward, inward});
  }
  return planes;
}

}  // namespace tetfsi::run
