#include "fluid/io/voxel_sampling.hpp"

#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "fluid/advection/point_locator.hpp"

namespace tetfsi::fluid {

double VoxelRange::count() const {
  double n = 1;
  for (int a = 0; a < 3; ++a) n *= std::max(0.0, double(last[a]) - double(first[a]) + 1.0);
  return n;
}

VoxelRange voxel_range(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double voxel_size) {
  if (!(voxel_size > 0)) throw std::invalid_argument("voxel_range: voxel size must be > 0");
  VoxelRange r;
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(lo[a] / voxel_size), l = std::ceil(hi[a] / voxel_size);
    if (!(std::fabs(f) < 2e9 && std::fabs(l) < 2e9))
      throw std::invalid_argument("voxel_range: voxel indices beyond 2e9 (voxel size too small)");
    r.first[a] = int(f);
    r.last[a] = int(l);
  }
  return r;
}

VoxelRange voxel_range(const FluidMesh& mesh, double voxel_size) {
  Eigen::Vector3d lo = mesh.nodes.at(0), hi = lo;
  for (const auto& x : mesh.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return voxel_range(lo, hi, voxel_size);
}

VoxelSamples sample_voxels(const FluidMesh& mesh, const NodalFields& nodal, double voxel_size) {
  const VoxelRange range = voxel_range(mesh, voxel_size);
  const Eigen::Vector3i n = (range.last - range.first).array() + 1;
  VoxelSamples out;
  out.voxel_size = voxel_size;
  if ((n.array() <= 0).any()) return out;
  const PointLocator locator(mesh);
  const int rows = n.y() * n.z();
  std::vector<VoxelSamples> row(rows);
  tbb::parallel_for(0, rows, [&](int r) {
    VoxelSamples& s = row[r];
    const int j = range.first.y() + r % n.y(), k = range.first.z() + r / n.y();
    int hint = -1;
    for (int i = range.first.x(); i <= range.last.x(); ++i) {
      const Eigen::Vector3d x = Eigen::Vector3d(i, j, k) * voxel_size;
      const Location l = locator.locate(x, hint);
      if (l.tet >= 0) hint = l.tet;
      if (!l.inside) continue;
      const auto& t = mesh.tets[l.tet];
      double smoke = 0, temperature = 0;
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      for (int c = 0; c < 4; ++c) {
        smoke += l.bary[c] * nodal.smoke[t[c]];
        temperature += l.bary[c] * nodal.temperature[t[c]];
        u += l.bary[c] * nodal.velocity[t[c]];
      }
      s.index.emplace_back(i, j, k);
      s.smoke.push_back(float(smoke));
      s.temperature.push_back(float(temperature));
      s.velocity.push_back(u.cast<float>());
    }
  });
  std::size_t total = 0;
  for (const auto& s : row) total += s.size();
  out.index.reserve(total);
  out.smoke.reserve(total);
  out.temperature.reserve(total);
  out.velocity.reserve(total);
  for (const auto& s : row) {
    out.index.insert(out.index.end(), s.index.begin(), s.index.end());
    out.smoke.insert(out.smoke.end(), s.smoke.begin(), s.smoke.end());
    out.temperature.insert(out.temperature.end(), s.temperature.begin(), s.temperature.end());
    out.velocity.insert(out.velocity.end(), s.velocity.begin(), s.velocity.end());
  }
  return out;
}

}  // namespace tetfsi::fluid
