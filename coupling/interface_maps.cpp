#include "coupling/interface_maps.hpp"

#include <stdexcept>
#include <string>

namespace tetfsi::coupling {

Eigen::SparseMatrix<double> interface_flux_map(const std::vector<InterfaceTriangle>& triangles,
                                               const InterfaceDofs& dofs, int num_pressures,
                                               int num_solid_nodes) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(27 * triangles.size());
  const int num_vertices = static_cast<int>(dofs.solid_node.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    for (int v : tri.vertices) {
      if (v < 0 || v >= num_vertices || v >= static_cast<int>(dofs.pressure_index.size()))
        throw std::invalid_argument("interface triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(v) + " outside the mesh");
      if (dofs.solid_node[v] < 0 || dofs.solid_node[v] >= num_solid_nodes)
        throw std::invalid_argument("interface triangle " + std::to_string(t) + ": vertex " + std::to_string(v) +
                                    " is not a node of the solid");
    }
    // M_ia A n: the exact integral of ψ_i φ_a n over the (wet part of the) flat triangle.
    for (int ki = 0; ki < 3; ++ki) {
      const int i = tri.vertices[ki];
      const int row = dofs.pressure_index[i];
      if (row < 0) continue;
      if (row >= num_pressures)
        throw std::invalid_argument("interface triangle " + std::to_string(t) + ": pressure index " +
                                    std::to_string(row) + " out of range");
      for (int ka = 0; ka < 3; ++ka) {
        const double w = tri.mass[ki][ka];
        if (w == 0.0) continue;
        const int col = 3 * dofs.solid_node[tri.vertices[ka]];
        for (int c = 0; c < 3; ++c) entries.emplace_back(row, col + c, w * tri.area_normal[c]);
      }
    }
  }
  Eigen::SparseMatrix<double> H(num_pressures, 3 * num_solid_nodes);
  H.setFromTriplets(entries.begin(), entries.end());  // sums duplicates: deterministic order
  return H;
}

}  // namespace tetfsi::coupling
