#include "mesh/incidence.hpp"

namespace tetfsi::mesh {
namespace {

template <class NodeOf>
VertexIncidence incidence(int num_vertices, int num_elements, int npe, NodeOf node) {
  VertexIncidence inc;
  inc.start.assign(num_vertices + 1, 0);
  for (int e = 0; e < num_elements; ++e)
    for (int i = 0; i < npe; ++i) ++inc.start[node(e, i) + 1];
  for (int v = 0; v < num_vertices; ++v) inc.start[v + 1] += inc.start[v];
  inc.element.resize(static_cast<std::size_t>(num_elements) * npe);
  inc.local.resize(inc.element.size());
  std::vector<int> fill(inc.start.begin(), inc.start.end() - 1);
  for (int e = 0; e < num_elements; ++e)
    for (int i = 0; i < npe; ++i) {
      const int k = fill[node(e, i)]++;
      inc.element[k] = e;
      inc.local[k] = i;
    }
  return inc;
}

}  // namespace

VertexIncidence vertex_incidence(int num_vertices, int nodes_per_element, const std::vector<int>& elements) {
  return incidence(num_vertices, static_cast<int>(elements.size()) / nodes_per_element, nodes_per_element,
                   [&](int e, int i) { return elements[e * nodes_per_element + i]; });
}

VertexIncidence vertex_incidence(const TetMesh& mesh) {
  return incidence(mesh.num_vertices(), mesh.num_tets(), 4, [&](int t, int i) { return mesh.tets[t][i]; });
}

}  // namespace tetfsi::mesh
