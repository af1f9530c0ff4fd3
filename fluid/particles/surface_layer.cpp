#include "fluid/particles/surface_layer.hpp"

#include <stdexcept>

#include <tbb/parallel_for.h>

namespace tetfsi::fluid {

void smooth_surface_layer(const FluidMesh& mesh, const std::vector<double>& liquid_volume, TetVectors& v) {
  if (static_cast<int>(liquid_volume.size()) != mesh.num_tets() || static_cast<int>(v.size()) != mesh.num_tets())
    throw std::invalid_argument("smooth_surface_layer: sizes do not match the mesh");
  TetVectors smoothed(mesh.num_tets());
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    smoothed[t] = v[t];
    if (!(liquid_volume[t] > 0 && liquid_volume[t] < kSurfaceLayerFraction * mesh.volume[t])) return;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int node : mesh.tets[t]) {  // each node has t's liquid at least: its weight is positive
      Eigen::Vector3d U = Eigen::Vector3d::Zero();
      double weight = 0;
      for (int s : mesh.node_tets[node]) {
        U += liquid_volume[s] * v[s];
        weight += liquid_volume[s];
      }
      sum += U / weight;
    }
    smoothed[t] = 0.25 * sum;
  });
  v = std::move(smoothed);
}

}  // namespace tetfsi::fluid
