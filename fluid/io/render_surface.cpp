#include "fluid/io/render_surface.hpp"

#include <algorithm>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "fluid/advection/point_locator.hpp"
#include "fluid/io/level_set_voxels.hpp"
#include "fluid/io/surface_voxels.hpp"
#include "fluid/io/vdb_surface.hpp"
#include "fluid/liquid/level_set.hpp"

namespace tetfsi::fluid {
namespace {

/// Vertices per chunk of the parallel velocity interpolation; fixed, so that each chunk's walk
/// (from the chunk's previous vertex) does not depend on the thread count.
constexpr int kChunk = 512;

/// Half-width of the band of mesh voxels around the smoothed surface [voxels]: the iso shift stays
/// within half of it (vdb_surface.hpp).
constexpr double kMeshBand = 6;

/// Area-weighted vertex normals of a closed, outward-oriented surface (unit; zero if degenerate).
std::vector<Eigen::Vector3d> vertex_normals(const mesh::SurfaceMesh& s) {
  std::vector<Eigen::Vector3d> n(s.vertices.size(), Eigen::Vector3d::Zero());
  for (const auto& t : s.triangles) {
    const Eigen::Vector3d a = (s.vertices[t[1]] - s.vertices[t[0]]).cross(s.vertices[t[2]] - s.vertices[t[0]]);
    for (int k = 0; k < 3; ++k) n[t[k]] += a;
  }
  for (auto& v : n)
    if (v.norm() > 0) v.normalize();
  return n;
}

std::vector<Eigen::Vector3d> vertex_velocity(const FluidMesh& mesh, const TetVectors& velocity,
                                             const mesh::SurfaceMesh& surface, double voxel_size) {
  const TetVectors nodal = average_to_nodes(mesh, velocity);
  const PointLocator locator(mesh);
  const std::vector<Eigen::Vector3d> normal = vertex_normals(surface);
  const int n = static_cast<int>(surface.vertices.size()), chunks = (n + kChunk - 1) / kChunk;
  std::vector<Eigen::Vector3d> out(n, Eigen::Vector3d::Zero());
  std::vector<char> found(n, 0);
  tbb::parallel_for(0, chunks, [&](int c) {
    int hint = -1;
    for (int v = c * kChunk; v < std::min(n, (c + 1) * kChunk); ++v) {
      Location l = locator.locate(surface.vertices[v], hint);
      // A vertex on a wall or a solid may lie outside the fluid by round-off or by the mesher's
      // linear crossings: try half a voxel inside the surface.
      if (!l.inside) l = locator.locate(surface.vertices[v] - 0.5 * voxel_size * normal[v], -1);
      if (!l.inside) continue;
      hint = l.tet;
      const auto& t = mesh.tets[l.tet];
      for (int k = 0; k < 4; ++k) out[v] += l.bary[k] * nodal[t[k]];
      found[v] = 1;
    }
  });
  // Vertices still outside (on the edge where the surface meets a sloping wall, whose normal
  // points into the wall): the mean of their neighbours', a ring at a time.
  std::vector<std::vector<int>> ring(n);
  for (const auto& t : surface.triangles)
    for (int k = 0; k < 3; ++k) ring[t[k]].push_back(t[(k + 1) % 3]);
  for (int pass = 0; pass < 4; ++pass) {
    std::vector<std::pair<int, Eigen::Vector3d>> filled;
    for (int v = 0; v < n; ++v) {
      if (found[v]) continue;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int count = 0;
      for (int w : ring[v])
        if (found[w]) sum += out[w], ++count;
      if (count) filled.emplace_back(v, sum / count);
    }
    if (filled.empty()) break;
    for (const auto& [v, u] : filled) out[v] = u, found[v] = 1;
  }
  return out;
}

}  // namespace

RenderSurface render_surface(const FluidMesh& mesh, const Eigen::VectorXd& phi, const TetVectors& velocity,
                             const RenderSurfaceOptions& options) {
  if (!(options.voxel_size > 0)) throw std::invalid_argument("render_surface: the voxel size must be positive");
  if (!(options.smoothing >= 0)) throw std::invalid_argument("render_surface: the smoothing must be >= 0");
  if (phi.size() != mesh.num_nodes()) throw std::invalid_argument("render_surface: phi does not match the mesh");
  RenderSurface out;
  out.liquid_volume = options.target_volume >= 0 ? options.target_volume : liquid_volume(mesh, phi);
  // The smoothing runs on voxels of at most sigma / 2 (surface_voxels.hpp: its cost grows as
  // (sigma / h)^5) over its band; the mesh on voxels of the size asked for, within kMeshBand of
  // the smoothed surface and along the walls the liquid touches. Samples reach one voxel beyond
  // the smoothing's band, so that every fluid voxel next to one in it is sampled.
  const double h = options.voxel_size, coarse_h = std::max(h, 0.5 * options.smoothing);
  const double band = (smoothing_band_voxels(options.smoothing / coarse_h) + 1) * coarse_h;
  const BoundaryTriangles walls = boundary_near_liquid(mesh, phi, band);
  // The liquid beyond the band: tets below -band at every node (of phi_s at the nodes, on fine voxels).
  auto deep = [&](const Eigen::VectorXd& values, double level) {
    return sample_level_set_voxels(mesh, phi, h, band, tets_below(mesh, values, level)).index;
  };
  const std::vector<char> coarse_tets = tets_near_zero(mesh, phi, band, coarse_h == h);
  SurfaceVoxels voxels = smooth_level_set(sample_level_set_voxels(mesh, phi, coarse_h, band, coarse_tets), walls,
                                          options.smoothing, coarse_h == h ? deep(phi, -band) : std::vector<Eigen::Vector3i>{});
  if (coarse_h > h) {
    const Eigen::VectorXd smoothed = smoothed_at(voxels, mesh.nodes, phi);
    voxels = resample(
        voxels, sample_level_set_voxels(mesh, phi, h, band, tets_near_zero(mesh, smoothed, kMeshBand * h, true)),
        walls, deep(smoothed, -kMeshBand * h));
  }
  VdbSurfaceOptions vdb;
  vdb.target_volume = out.liquid_volume;
  vdb.volume_tolerance = options.volume_tolerance;
  vdb.max_shift = coarse_h > h ? 0.5 * kMeshBand * h : 0.5 * band;
  VdbSurface s = mesh_liquid_voxels(voxels, walls, vdb);
  out.surface = std::move(s.surface);
  out.enclosed_volume = s.enclosed_volume;
  out.iso_shift = s.iso_shift;
  out.velocity = vertex_velocity(mesh, velocity, out.surface, options.voxel_size);
  return out;
}

}  // namespace tetfsi::fluid
