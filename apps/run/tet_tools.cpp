#include "apps/run/tet_tools.hpp"

#include <algorithm>
#include <map>

#include "mesh/interface.hpp"

namespace tetfsi::run {

mesh::TetMesh extract_subdomain(const mesh::TetMesh& m, int subdomain) {
  mesh::TetMesh out;
  std::vector<int> map(m.vertices.size(), -1);
  for (int t = 0; t < m.num_tets(); ++t) {
    const int label = m.subdomain.empty() ? subdomain : m.subdomain[t];
    if (label != subdomain) continue;
    std::array<int, 4> tet;
    for (int k = 0; k < 4; ++k) {
      int& v = map[m.tets[t][k]];
      if (v < 0) {
        v = out.num_vertices();
        out.vertices.push_back(m.vertices[m.tets[t][k]]);
      }
      tet[k] = v;
    }
    out.tets.push_back(tet);
    out.subdomain.push_back(subdomain);
  }
  return out;
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

}  // namespace tetfsi::run
