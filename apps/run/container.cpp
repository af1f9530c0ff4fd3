#include "apps/run/container.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <regex>

#include "apps/run/scene_values.hpp"
#include "apps/run/solid_geometry.hpp"
#include "mesh/primitives.hpp"
#include "mesh/surface_distance.hpp"

namespace tetfsi::run {

mesh::SurfaceMesh container_surface(const scene::Json& domain) {
  if (!domain.contains("container")) return {};
  const auto& c = domain["container"];
  const auto type = c.at("type").get<std::string>();
  if (type == "box") return {};
  if (type == "mesh") {
    std::vector<std::string> warnings;  // reported by the preflight, which reads the same file
    return placed_surface_file(c, "container", warnings);
  }
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

InputError meshing_failure(const mesh::MeshError& error, const std::vector<std::string>& names) {
  static const std::regex solid_index("solid ([0-9]+)");
  const std::string what = error.what();
  std::string message;
  auto from = what.cbegin();
  for (std::sregex_iterator m(what.begin(), what.end(), solid_index), end; m != end; ++m) {
    message.append(from, (*m)[0].first);
    const std::size_t i = std::stoul((*m)[1].str());
    message += i < names.size() ? "solid '" + names[i] + "' (/solids/" + std::to_string(i) + ")" : (*m)[0].str();
    from = (*m)[0].second;
  }
  message.append(from, what.cend());
  return InputError("meshing failed: " + message);
}

mesh::TetMesh mesh_container(const scene::Json& domain, const std::vector<mesh::SurfaceMesh>& solids,
                             const mesh::MeshSizing& sizing, const std::vector<mesh::SurfaceMesh>& cavities) {
  const mesh::SurfaceMesh container = container_surface(domain);
  if (container.vertices.empty())
    return mesh::build_complex(vec3(domain.at("lo")), vec3(domain.at("hi")), solids, sizing, cavities);
  return mesh::build_complex(container, solids, sizing, cavities);
}

void ContainerWalls::add_to(solid::StaticObstacles& obstacles) const {
  for (const auto& p : planes) obstacles.add_plane(p);
  for (const auto& s : spheres) obstacles.add_sphere_interior(s);
  for (const auto& c : cylinders) obstacles.add_cylinder_interior(c);
  for (const auto& o : implicits) obstacles.add_implicit(o);
}

ContainerWalls container_walls(const scene::Json& domain, double gap) {
  ContainerWalls walls;
  const std::string type = domain.contains("container") ? domain["container"].at("type").get<std::string>() : "box";
  if (type == "box") {
    const Eigen::Vector3d lo = vec3(domain.at("lo")), hi = vec3(domain.at("hi"));
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d n = Eigen::Vector3d::Unit(axis);
      walls.planes.push_back({lo + gap * n, n});
      walls.planes.push_back({hi - gap * n, -n});
    }
    return walls;
  }
  if (type == "mesh") {
    // The file's surface set back by the gap: phi = -d(x) - gap, d the signed distance (negative
    // inside), the normal from the nearest surface point toward the inside. The fluid is meshed in
    // CGAL's approximation of the surface, within facet_distance (an edge / 10) of it, below the
    // default gap (half an edge), so a node the walls hold stays in the meshed fluid.
    auto distance = std::make_shared<mesh::SurfaceDistance>(container_surface(domain));
    walls.implicits.push_back({[distance, gap](const Eigen::Vector3d& x, Eigen::Vector3d& normal) {
      Eigen::Vector3d nearest;
      const double d = (*distance)(x, nearest);
      const Eigen::Vector3d r = x - nearest;
      normal = r.norm() > 0 ? Eigen::Vector3d((d < 0 ? 1.0 : -1.0) * r.normalized()) : Eigen::Vector3d::UnitZ();
      return -d - gap;
    }});
    return walls;
  }
  const auto& c = domain["container"];
  const Eigen::Vector3d center = vec3(c.at("center"));
  if (type == "sphere") {
    // The icosphere's faces lie inside the sphere: the nearest face plane bounds the fluid.
    const mesh::SurfaceMesh surface = container_surface(domain);
    double inradius = c.at("radius").get<double>();
    for (const auto& t : surface.triangles) {
      const Eigen::Vector3d& a = surface.vertices[t[0]];
      const Eigen::Vector3d n = (surface.vertices[t[1]] - a).cross(surface.vertices[t[2]] - a).normalized();
      inradius = std::min(inradius, std::abs((a - center).dot(n)));
    }
    walls.spheres.push_back({center, inradius - gap});
    return walls;
  }
  // cylinder: the prism over a regular polygon inscribed in the circle, its axis one of x, y, z.
  const double kPi = std::acos(-1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d::Unit(std::string("xyz").find(c.at("axis").get<std::string>()[0]));
  const double half = 0.5 * c.at("length").get<double>();
  walls.cylinders.push_back({center, axis, c.at("radius").get<double>() * std::cos(kPi / c.at("segments").get<int>()) - gap});
  walls.planes.push_back({center - (half - gap) * axis, axis});
  walls.planes.push_back({center + (half - gap) * axis, -axis});
  return walls;
}

}  // namespace tetfsi::run
