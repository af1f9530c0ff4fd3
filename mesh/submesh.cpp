#include "mesh/submesh.hpp"

#include <stdexcept>
#include <string>

namespace tetfsi::mesh {

Submesh extract_subdomain(const TetMesh& mesh, int subdomain) {
  Submesh s;
  s.from_parent_vertex.assign(mesh.vertices.size(), -1);
  std::vector<char> used(mesh.vertices.size(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain.empty() || mesh.subdomain[t] == subdomain)
      for (int v : mesh.tets[t]) used[v] = 1;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (used[v]) {
      s.from_parent_vertex[v] = static_cast<int>(s.to_parent_vertex.size());
      s.to_parent_vertex.push_back(v);
      s.mesh.vertices.push_back(mesh.vertices[v]);
    }
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain.empty() || mesh.subdomain[t] == subdomain) {
      std::array<int, 4> tet{};
      for (int k = 0; k < 4; ++k) tet[k] = s.from_parent_vertex[mesh.tets[t][k]];
      s.mesh.tets.push_back(tet);
      s.mesh.subdomain.push_back(subdomain);
      s.to_parent_tet.push_back(t);
    }
  if (s.mesh.tets.empty())
    throw std::invalid_argument("extract_subdomain: no tet has label " + std::to_string(subdomain));
  return s;
}

}  // namespace tetfsi::mesh
