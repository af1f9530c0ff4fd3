#include "fluid/io/surface_voxels.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <openvdb/math/Proximity.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Morphology.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace tetfsi::fluid {
namespace {

/// Voxel (lattice index) -> position in the SurfaceVoxels arrays, in an OpenVDB tree (sparse, with
/// cached accessors: an order of magnitude faster than a hash map here). Reads from several threads
/// each use their own accessor.
class VoxelMap {
 public:
  VoxelMap() : tree_(std::make_unique<openvdb::Int32Tree>(-1)) {}
  static openvdb::Coord coord(const Eigen::Vector3i& c) { return openvdb::Coord(c.x(), c.y(), c.z()); }
  void set(const Eigen::Vector3i& c, int v) { tree_->setValue(coord(c), v); }
  /// Maps index[v] to v for every v.
  void set_all(const std::vector<Eigen::Vector3i>& index) {
    openvdb::tree::ValueAccessor<openvdb::Int32Tree> acc(*tree_);
    for (std::size_t v = 0; v < index.size(); ++v) acc.setValue(coord(index[v]), static_cast<int>(v));
  }
  const openvdb::Int32Tree& tree() const { return *tree_; }
  /// A reader for one thread.
  class Reader {
   public:
    explicit Reader(const openvdb::Int32Tree& tree) : acc_(tree) {}
    int operator()(const Eigen::Vector3i& c) const { return acc_.getValue(coord(c)); }
   private:
    openvdb::tree::ValueAccessor<const openvdb::Int32Tree> acc_;
  };
  Reader reader() const { return Reader(*tree_); }

 private:
  std::unique_ptr<openvdb::Int32Tree> tree_;
};

VoxelMap make_map(const std::vector<Eigen::Vector3i>& index) {
  VoxelMap map;
  map.set_all(index);
  return map;
}

/// Adds two layers of voxels next to the sampled ones (26-neighbours), in the tree's order per
/// layer, leaving out the deep liquid (s.deep: in the fluid, not beyond a wall; voxels of the air
/// beyond the band may join: they are outside the liquid either way).
void add_continuation(SurfaceVoxels& s, VoxelMap& map) {
  openvdb::MaskTree deep;
  {
    openvdb::tree::ValueAccessor<openvdb::MaskTree> acc(deep);
    for (const auto& c : s.deep) acc.setValueOn(VoxelMap::coord(c));
  }
  for (int layer = 0; layer < 2; ++layer) {
    openvdb::MaskTree ring(map.tree(), false, openvdb::TopologyCopy());
    openvdb::MaskTree known(ring, false, openvdb::TopologyCopy());
    openvdb::tools::dilateActiveValues(ring, 1, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
    ring.topologyDifference(known);
    ring.topologyDifference(deep);
    const std::size_t first = s.size();
    for (auto it = ring.cbeginValueOn(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      s.index.emplace_back(c.x(), c.y(), c.z());
      s.phi.push_back(float(s.band));
      s.inside.push_back(0);
    }
    for (std::size_t v = first; v < s.size(); ++v) map.set(s.index[v], static_cast<int>(v));
  }
}

/// D and the nearest triangle (file doc), from each triangle's neighbourhood.
void wall_distance(const BoundaryTriangles& walls, const VoxelMap& map, SurfaceVoxels& s) {
  const double h = s.voxel_size, cap = kWallBandVoxels * h;
  const VoxelMap::Reader find = map.reader();
  std::vector<float> u(s.size(), float(s.band));
  s.nearest.assign(s.size(), -1);
  for (int t = 0; t < static_cast<int>(walls.triangles.size()); ++t) {
    const auto& tri = walls.triangles[t];
    const openvdb::Vec3d a(walls.points[tri[0]].data()), b(walls.points[tri[1]].data()), c(walls.points[tri[2]].data());
    Eigen::Vector3d lo = walls.points[tri[0]].cwiseMin(walls.points[tri[1]]).cwiseMin(walls.points[tri[2]]);
    Eigen::Vector3d hi = walls.points[tri[0]].cwiseMax(walls.points[tri[1]]).cwiseMax(walls.points[tri[2]]);
    lo.array() -= cap;
    hi.array() += cap;
    for (int k = int(std::ceil(lo.z() / h)); k <= int(std::floor(hi.z() / h)); ++k)
      for (int j = int(std::ceil(lo.y() / h)); j <= int(std::floor(hi.y() / h)); ++j)
        for (int i = int(std::ceil(lo.x() / h)); i <= int(std::floor(hi.x() / h)); ++i) {
          const int v = find(Eigen::Vector3i(i, j, k));
          if (v < 0) continue;
          const openvdb::Vec3d x(i * h, j * h, k * h);
          openvdb::Vec3d uvw;
          const float d = float((openvdb::math::closestPointOnTriangleToPoint(a, b, c, x, uvw) - x).length());
          if (d < cap && d < u[v]) {
            u[v] = d;
            s.nearest[v] = t;
          }
        }
  }
  s.wall.resize(s.size());
  for (std::size_t v = 0; v < s.size(); ++v) {
    // A voxel centre on a wall (within round-off) is on the zero set of D: 0, not +-round-off, so
    // that which side it counts on does not depend on the last bit of its distance.
    const float d = u[v] < 1e-5f * float(h) ? 0.0f : u[v];
    s.wall[v] = s.inside[v] ? -d : d;
  }
}

/// Whether fluid voxels a and b (neighbours) lie on opposite sides of the plane of the boundary
/// triangle nearest either: a wall (a solid, however thin) between them.
bool wall_between(const SurfaceVoxels& s, const BoundaryTriangles& walls, int a, int b) {
  for (const auto [from, to] : {std::pair{a, b}, std::pair{b, a}}) {
    const int t = s.nearest[from];
    if (t < 0) continue;
    const Eigen::Vector3d& p = walls.points[walls.triangles[t][0]];
    if (walls.normals[t].dot(s.index[to].cast<double>() * s.voxel_size - p) > 0) return true;
  }
  return false;
}

/// The heat equation on the fluid voxels in the band (file doc), in place on s.phi.
void diffuse(SurfaceVoxels& s, const BoundaryTriangles& walls, const VoxelMap& map, std::size_t sampled,
             double sigma) {
  std::vector<int> active;  // sampled voxels in the band, in their order
  for (std::size_t v = 0; v < sampled; ++v)
    if (std::abs(s.phi[v]) < s.band) active.push_back(static_cast<int>(v));
  // Per active voxel and axis, its two neighbours (-1: not fluid, or behind a wall).
  std::vector<std::array<int, 6>> link(active.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(active.size()), 512), [&](const auto& range) {
    const VoxelMap::Reader find = map.reader();
    for (int k = range.begin(); k < range.end(); ++k) {
      const int v = active[k];
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
          Eigen::Vector3i c = s.index[v];
          c[axis] += side ? 1 : -1;
          int n = find(c);
          if (n >= 0 && (!s.inside[n] || wall_between(s, walls, v, n))) n = -1;
          link[k][2 * axis + side] = n;
        }
    }
  });
  const double h2 = s.voxel_size * s.voxel_size;
  const double dt_over_h2 = 0.5 * sigma * sigma / s.steps / h2;  // <= 1/6
  std::vector<float> next(active.size());
  for (int step = 0; step < s.steps; ++step) {
    tbb::parallel_for(0, static_cast<int>(active.size()), [&](int k) {
      const int v = active[k];
      double laplacian = 0;  // h^2 times; an axis with a wall side counts 0 (linear continuation)
      for (int axis = 0; axis < 3; ++axis) {
        const int m = link[k][2 * axis], p = link[k][2 * axis + 1];
        if (m >= 0 && p >= 0) laplacian += double(s.phi[m]) - 2.0 * s.phi[v] + double(s.phi[p]);
      }
      next[k] = float(s.phi[v] + dt_over_h2 * laplacian);
    });
    for (std::size_t k = 0; k < active.size(); ++k) s.phi[active[k]] = next[k];
  }
}

/// phi on the continuation voxels, layer by layer (file doc).
void continue_level_set(SurfaceVoxels& s, const VoxelMap& map, std::size_t sampled) {
  std::vector<char> known(s.size(), 0);
  std::fill(known.begin(), known.begin() + sampled, 1);
  const VoxelMap::Reader find = map.reader();
  auto value = [&](const Eigen::Vector3i& c) { const int n = find(c); return n >= 0 && known[n] ? n : -1; };
  std::size_t begin = sampled;
  while (begin < s.size()) {
    // One layer: the voxels with a known neighbour, all computed from the layers before.
    std::vector<std::pair<int, float>> layer;
    for (std::size_t v = begin; v < s.size(); ++v) {
      if (known[v]) continue;
      double linear = 0, mean = 0;
      int lines = 0, neighbours = 0;
      for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
          Eigen::Vector3i step = Eigen::Vector3i::Zero();
          step[axis] = side;
          const int a = value(s.index[v] + step), b = value(s.index[v] + 2 * step);
          if (a >= 0 && b >= 0) linear += 2.0 * s.phi[a] - s.phi[b], ++lines;
        }
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (const int n = value(s.index[v] + Eigen::Vector3i(dx, dy, dz)); n >= 0) mean += s.phi[n], ++neighbours;
      if (lines) layer.emplace_back(int(v), float(linear / lines));
      else if (neighbours) layer.emplace_back(int(v), float(mean / neighbours));
    }
    if (layer.empty()) break;
    for (const auto& [v, phi] : layer) {
      s.phi[v] = std::clamp(phi, -float(s.band), float(s.band));
      known[v] = 1;
    }
    while (begin < s.size() && known[begin]) ++begin;  // layers are contiguous: the first unknown
  }
}

/// phi_s at fine voxel v (index coordinates on the fine lattice): trilinear in the coarse voxels
/// around it; for a voxel in the fluid, leaving out corners behind the plane of its nearest
/// boundary triangle (the other side of a thin wall) and weighting the rest anew, the sampled
/// value if none is left.
float coarse_value(const SurfaceVoxels& coarse, const VoxelMap::Reader& find, const SurfaceVoxels& fine,
                   const BoundaryTriangles& walls, int v) {
  const Eigen::Vector3d x = fine.index[v].cast<double>() * fine.voxel_size;
  const Eigen::Vector3d q = x / coarse.voxel_size;
  const Eigen::Vector3i c0 = q.array().floor().cast<int>();
  const Eigen::Vector3d t = q - c0.cast<double>();
  double sum = 0, weight = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3i c = c0 + Eigen::Vector3i(k & 1, k >> 1 & 1, k >> 2 & 1);
    const double w = ((k & 1) ? t.x() : 1 - t.x()) * ((k >> 1 & 1) ? t.y() : 1 - t.y()) * ((k >> 2 & 1) ? t.z() : 1 - t.z());
    if (fine.inside[v] && fine.nearest[v] >= 0) {
      const int tri = fine.nearest[v];
      const Eigen::Vector3d& p = walls.points[walls.triangles[tri][0]];
      if (walls.normals[tri].dot(c.cast<double>() * coarse.voxel_size - p) > 0) continue;
    }
    const int n = find(c);
    // A corner not sampled lies beyond the coarse band: deep in the liquid or far in the air.
    sum += w * (n >= 0 ? coarse.phi[n] : (fine.phi[v] < 0 ? -coarse.band : coarse.band));
    weight += w;
  }
  return weight > 1e-6 ? float(sum / weight) : fine.phi[v];
}

}  // namespace

Eigen::VectorXd smoothed_at(const SurfaceVoxels& coarse, const std::vector<Eigen::Vector3d>& points,
                            const Eigen::VectorXd& fallback) {
  const VoxelMap map = make_map(coarse.index);
  Eigen::VectorXd out(points.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(points.size()), 512), [&](const auto& range) {
    const VoxelMap::Reader find = map.reader();
    for (int p = range.begin(); p < range.end(); ++p) {
      const Eigen::Vector3d q = points[p] / coarse.voxel_size;
      const Eigen::Vector3i c0 = q.array().floor().cast<int>();
      const Eigen::Vector3d t = q - c0.cast<double>();
      double sum = 0;
      for (int k = 0; k < 8; ++k) {
        const int n = find(c0 + Eigen::Vector3i(k & 1, k >> 1 & 1, k >> 2 & 1));
        const double w =
            ((k & 1) ? t.x() : 1 - t.x()) * ((k >> 1 & 1) ? t.y() : 1 - t.y()) * ((k >> 2 & 1) ? t.z() : 1 - t.z());
        sum += w * (n >= 0 ? coarse.phi[n] : (fallback[p] < 0 ? -coarse.band : coarse.band));
      }
      out[p] = sum;
    }
  });
  return out;
}

SurfaceVoxels resample(const SurfaceVoxels& coarse, const LevelSetVoxels& fine_samples, const BoundaryTriangles& walls,
                       std::vector<Eigen::Vector3i> deep) {
  SurfaceVoxels s;
  s.voxel_size = fine_samples.voxel_size;
  s.band = coarse.band;
  s.steps = coarse.steps;
  s.index = fine_samples.index;
  s.phi = fine_samples.phi;
  s.inside.assign(fine_samples.size(), 1);
  s.deep = std::move(deep);
  VoxelMap map = make_map(fine_samples.index);
  const VoxelMap coarse_map = make_map(coarse.index);
  add_continuation(s, map);
  wall_distance(walls, map, s);
  std::vector<float> phi(s.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(s.size()), 512), [&](const auto& range) {
    const VoxelMap::Reader find = coarse_map.reader();
    for (int v = range.begin(); v < range.end(); ++v) phi[v] = coarse_value(coarse, find, s, walls, v);
  });
  for (std::size_t v = 0; v < s.size(); ++v) s.phi[v] = std::clamp(phi[v], -float(s.band), float(s.band));
  for (std::size_t v = 0; v < s.size(); ++v)
    if (std::abs(s.wall[v]) >= kWallBandVoxels * s.voxel_size) s.wall[v] = s.wall[v] < 0 ? -float(s.band) : float(s.band);
  return s;
}

int smoothing_steps(double sigma_voxels) {
  return sigma_voxels > 0 ? static_cast<int>(std::ceil(3.0 * sigma_voxels * sigma_voxels)) : 0;
}

int smoothing_band_voxels(double sigma_voxels) {
  return static_cast<int>(std::ceil(3.0 * std::max(sigma_voxels, 0.0))) + 2;
}

SurfaceVoxels smooth_level_set(const LevelSetVoxels& voxels, const BoundaryTriangles& walls, double smoothing,
                               std::vector<Eigen::Vector3i> deep) {
  if (!(smoothing >= 0)) throw std::invalid_argument("smooth_level_set: the smoothing must be >= 0");
  if (!(voxels.voxel_size > 0)) throw std::invalid_argument("smooth_level_set: the voxel size must be positive");
  SurfaceVoxels s;
  s.voxel_size = voxels.voxel_size;
  const double sigma_voxels = smoothing / voxels.voxel_size;
  s.band = smoothing_band_voxels(sigma_voxels) * voxels.voxel_size;
  s.steps = smoothing_steps(sigma_voxels);
  s.index = voxels.index;
  s.phi = voxels.phi;
  s.inside.assign(voxels.size(), 1);
  s.deep = std::move(deep);
  VoxelMap map = make_map(voxels.index);
  add_continuation(s, map);
  wall_distance(walls, map, s);
  if (s.steps > 0) diffuse(s, walls, map, voxels.size(), smoothing);
  for (std::size_t v = 0; v < voxels.size(); ++v) s.phi[v] = std::clamp(s.phi[v], -float(s.band), float(s.band));
  continue_level_set(s, map, voxels.size());
  for (std::size_t v = 0; v < s.size(); ++v)
    if (std::abs(s.wall[v]) >= kWallBandVoxels * s.voxel_size) s.wall[v] = s.wall[v] < 0 ? -float(s.band) : float(s.band);
  return s;
}

}  // namespace tetfsi::fluid
