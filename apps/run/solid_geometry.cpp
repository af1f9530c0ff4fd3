#include "apps/run/solid_geometry.hpp"

#include <cmath>
#include <map>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include "apps/run/errors.hpp"

namespace tetfsi::run {
namespace {

Eigen::Vector3d vec3(const scene::Json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

/// Every edge must be used exactly twice, once in each direction (closed, manifold, oriented).
std::string surface_defect(const mesh::SurfaceMesh& s) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    if (n > 1) return fmt::format("edge ({}, {}) is used by {} triangles in the same direction "
                                  "(non-manifold or inconsistently oriented)", e.first, e.second, n);
    if (!directed.count({e.second, e.first}))
      return fmt::format("edge ({}, {}) has only one triangle (the surface is open)", e.first, e.second);
  }
  return "";
}

}  // namespace

Eigen::Matrix3d euler_xyz_deg(const Eigen::Vector3d& deg) {
  const Eigen::Vector3d r = deg * (M_PI / 180.0);
  return (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX())).toRotationMatrix();
}

mesh::SurfaceMesh icosphere(double radius, int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  mesh::SurfaceMesh s;
  s.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  s.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      s.vertices.push_back(0.5 * (s.vertices[a] + s.vertices[b]));
      return midpoint[key] = s.num_vertices() - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& f : s.triangles) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.insert(next.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    s.triangles = std::move(next);
  }
  for (auto& v : s.vertices) v = radius * v.normalized();
  return s;
}

mesh::SurfaceMesh box_surface(const Eigen::Vector3d& size) {
  mesh::SurfaceMesh s;
  for (int i = 0; i < 8; ++i)
    s.vertices.push_back(0.5 * Eigen::Vector3d((i & 1) ? size.x() : -size.x(),
                                               (i & 2) ? size.y() : -size.y(),
                                               (i & 4) ? size.z() : -size.z()));
  s.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return s;
}

mesh::SurfaceMesh import_surface(const std::filesystem::path& file, double unit_scale) {
  Assimp::Importer importer;
  const aiScene* sc = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                           aiProcess_PreTransformVertices);
  if (!sc || !sc->mRootNode)
    throw InputError(fmt::format("{}: cannot read the surface: {}", file.string(), importer.GetErrorString()));
  mesh::SurfaceMesh s;
  for (unsigned m = 0; m < sc->mNumMeshes; ++m) {
    const aiMesh* am = sc->mMeshes[m];
    const int base = s.num_vertices();
    for (unsigned i = 0; i < am->mNumVertices; ++i)
      s.vertices.emplace_back(unit_scale * am->mVertices[i].x, unit_scale * am->mVertices[i].y,
                              unit_scale * am->mVertices[i].z);
    for (unsigned f = 0; f < am->mNumFaces; ++f)
      if (am->mFaces[f].mNumIndices == 3)
        s.triangles.push_back({base + static_cast<int>(am->mFaces[f].mIndices[0]),
                               base + static_cast<int>(am->mFaces[f].mIndices[1]),
                               base + static_cast<int>(am->mFaces[f].mIndices[2])});
  }
  if (s.triangles.empty()) throw InputError(fmt::format("{}: the file holds no triangles", file.string()));
  if (auto defect = surface_defect(s); !defect.empty())
    throw InputError(fmt::format("{}: not a closed, consistently oriented surface: {}", file.string(), defect));
  if (enclosed_volume(s) < 0)
    throw InputError(fmt::format("{}: the surface's normals point inwards; flip its triangles", file.string()));
  return s;
}

mesh::SurfaceMesh surface_of(const scene::Json& solid) {
  const auto& g = solid.at("geometry");
  const auto type = g.at("type").get<std::string>();
  mesh::SurfaceMesh s;
  if (type == "mesh") s = import_surface(g.at("file").get<std::string>(), g.at("unit_scale").get<double>());
  else if (type == "box") s = box_surface(vec3(g.at("size")));
  else if (type == "sphere") s = icosphere(g.at("radius").get<double>(), g.at("subdivisions").get<int>());
  else if (type == "sheet")
    s = box_surface({g.at("size")[0].get<double>(), g.at("thickness").get<double>(), g.at("size")[1].get<double>()});
  const auto& p = solid.at("placement");
  const Eigen::Matrix3d R = euler_xyz_deg(vec3(p.at("rotation_deg")));
  const Eigen::Vector3d t = vec3(p.at("translation"));
  for (auto& v : s.vertices) v = R * v + t;
  return s;
}

double enclosed_volume(const mesh::SurfaceMesh& s) {
  double v = 0;
  for (const auto& t : s.triangles)
    v += s.vertices[t[0]].dot(s.vertices[t[1]].cross(s.vertices[t[2]])) / 6.0;
  return v;
}

}  // namespace tetfsi::run
