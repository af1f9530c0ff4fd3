#include "apps/run/tet_tools.hpp"

#include <algorithm>
#include <map>

#include "mesh/interface.hpp"
#include "mesh/submesh.hpp"

namespace tetfsi::run {

mesh::TetMesh extract_subdomain(const mesh::TetMesh& m, int subdomain) {
  for (int label : m.subdomain)
    if (label == subdomain) return mesh::extract_subdomain(m, subdomain).mesh;
  return m.subdomain.empty() ? m : mesh::TetMesh{};
}

mesh::SurfaceMesh boundary_surface(const mesh::TetMesh& m, std::vector<int>* to_tet_vertex) {
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> count;
  for (const auto& t : m.tets)
    for (const auto& f : mesh::kTetFaceVertices) {
      std::array<int, 3> tri{t[f[0]], t[f[1]], t[f[2]]};
      auto key = tri;
      std::sort(key.begin(), key.end());
      auto& entry = count[key];
      ++entry.first;
      entry.second = tri;
    }
  mesh::SurfaceMesh s;
  std::vector<int> map(m.vertices.size(), -1);
  for (const auto& [key, entry] : count) {
    if (entry.first != 1) continue;
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      int& v = map[entry.second[k]];
      if (v < 0) {
        v = s.num_vertices();
        s.vertices.push_back(m.vertices[entry.second[k]]);
        if (to_tet_vertex) to_tet_vertex->push_back(entry.second[k]);
      }
      tri[k] = v;
    }
    s.triangles.push_back(tri);
  }
  return s;
}

double surface_area(const mesh::SurfaceMesh& s) {
  double a = 0;
  for (const auto& t : s.triangles)
    a += 0.5 * (s.vertices[t[1]] - s.vertices[t[0]]).cross(s.vertices[t[2]] - s.vertices[t[0]]).norm();
  return a;
}

double mean_edge_length(const mesh::SurfaceMesh& surface) {
  double sum = 0;
  for (const auto& t : surface.triangles)
    for (int k = 0; k < 3; ++k) sum += (surface.vertices[t[(k + 1) % 3]] - surface.vertices[t[k]]).norm();
  return surface.triangles.empty() ? 0.0 : sum / (3.0 * static_cast<double>(surface.triangles.size()));
}

}  // namespace tetfsi::run
