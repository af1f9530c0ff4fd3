#include "apps/run/tet_tools.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "mesh/interface.hpp"
#include "mesh/submesh.hpp"

namespace tetfsi::run {

mesh::TetMesh extract_subdomain(const mesh::TetMesh& m, int subdomain) {
  for (int label : m.subdomain)
    if (label == subdomain) return mesh::extract_subdomain(m, subdomain).mesh;
  return m.subdomain.empty() ? m : mesh::TetMesh{};
}

mesh::SurfaceMesh boundary_surface(const mesh::TetMesh& m, std::vector<int>* to_tet_vertex) {
  // Every tet face under its sorted vertex triple; after sorting, a boundary face is a triple that
  // occurs once. The faces come out in the order of their sorted triples.
  struct Face {
    std::array<int, 3> key, tri;
  };
  std::vector<Face> faces;
  faces.reserve(4 * m.tets.size());
  for (const auto& t : m.tets)
    for (const auto& f : mesh::kTetFaceVertices) {
      Face face{{t[f[0]], t[f[1]], t[f[2]]}, {t[f[0]], t[f[1]], t[f[2]]}};
      std::sort(face.key.begin(), face.key.end());
      faces.push_back(face);
    }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
  mesh::SurfaceMesh s;
  std::vector<int> map(m.vertices.size(), -1);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1) {
      std::array<int, 3> tri;
      for (int k = 0; k < 3; ++k) {
        int& v = map[faces[i].tri[k]];
        if (v < 0) {
          v = s.num_vertices();
          s.vertices.push_back(m.vertices[faces[i].tri[k]]);
          if (to_tet_vertex) to_tet_vertex->push_back(faces[i].tri[k]);
        }
        tri[k] = v;
      }
      s.triangles.push_back(tri);
    }
    i = j;
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

int nearest_node(const Eigen::VectorXd& X, const Eigen::Vector3d& x) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int a = 0; a < X.size() / 3; ++a) {
    const double d = (X.segment<3>(3 * a) - x).squaredNorm();
    if (d < best_d) best_d = d, best = a;
  }
  return best;
}

}  // namespace tetfsi::run
