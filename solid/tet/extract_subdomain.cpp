#include "solid/tet/extract_subdomain.hpp"

#include "solid/solid_error.hpp"

namespace tetfsi::solid {

SubdomainMesh extract_subdomain(const mesh::TetMesh& source, int subdomain) {
  SubdomainMesh out;
  std::vector<int> local(source.num_vertices(), -1);
  for (int t = 0; t < source.num_tets(); ++t) {
    if (!source.subdomain.empty() && source.subdomain[t] != subdomain) continue;
    std::array<int, 4> tet{};
    for (int i = 0; i < 4; ++i) {
      const int g = source.tets[t][i];
      if (local[g] < 0) {
        local[g] = static_cast<int>(out.global_vertex.size());
        out.global_vertex.push_back(g);
        out.mesh.vertices.push_back(source.vertices[g]);
      }
      tet[i] = local[g];
    }
    out.mesh.tets.push_back(tet);
    out.mesh.subdomain.push_back(subdomain);
    out.global_tet.push_back(t);
  }
  if (out.mesh.tets.empty())
    throw SolidError("extract_subdomain: no tet has subdomain label " + std::to_string(subdomain));
  return out;
}

}  // namespace tetfsi::solid
