#include "fluid/io/vdb_surface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include "fluid/io/vdb_fields.hpp"

namespace tetfsi::fluid {
namespace {

using vdb::Fields;
using vdb::place_on_sharp_edges;
using vdb::wall_distance_at;

using openvdb::Coord;
using openvdb::FloatGrid;
using openvdb::MaskGrid;

/// Stores v, clamped to [-band, band], at c: active inside the band, inactive (the level set's
/// inside or outside value) beyond it. The grids are not pruned: a leaf of inactive voxels of both
/// signs (known ones at -band beside unknown ones at the background +band) would become one tile of
/// the first voxel's sign.
template <class Accessor>
void set_band_value(Accessor& a, const Coord& c, float v, float band) {
  v = std::clamp(v, -band, band);
  if (std::abs(v) < band) a.setValue(c, v);
  else a.setValueOff(c, v);
}

FloatGrid::Ptr level_set_grid(const openvdb::math::Transform::Ptr& xf, float band) {
  FloatGrid::Ptr g = FloatGrid::create(band);
  g->setTransform(xf);
  g->setGridClass(openvdb::GRID_LEVEL_SET);
  return g;
}

/// The grids of `voxels`: phi_s and D (active within the band, +-band beyond), the nearest
/// triangles, and every voxel as known.
Fields grids(const SurfaceVoxels& voxels, const BoundaryTriangles& walls) {
  const auto xf = openvdb::math::Transform::createLinearTransform(voxels.voxel_size);
  Fields g;
  g.h = voxels.voxel_size;
  g.band = float(voxels.band);
  g.phi = level_set_grid(xf, g.band);
  g.wall = level_set_grid(xf, g.band);
  g.nearest = openvdb::Int32Grid::create(-1);
  g.nearest->setTransform(xf);
  g.known = MaskGrid::create();
  g.known->setTransform(xf);
  auto pa = g.phi->getAccessor();
  auto da = g.wall->getAccessor();
  auto na = g.nearest->getAccessor();
  auto ka = g.known->getAccessor();
  for (std::size_t v = 0; v < voxels.size(); ++v) {
    const Coord c(voxels.index[v].x(), voxels.index[v].y(), voxels.index[v].z());
    ka.setActiveState(c, true);
    set_band_value(pa, c, voxels.phi[v], g.band);
    set_band_value(da, c, voxels.wall[v], g.band);
    if (voxels.nearest[v] >= 0) na.setValue(c, voxels.nearest[v]);
  }
  g.deep = level_set_grid(xf, g.band);
  {
    auto ea = g.deep->getAccessor();
    for (const auto& c : voxels.deep) ea.setValueOff(Coord(c.x(), c.y(), c.z()), -g.band);
  }
  g.wall_normal = walls.normals;
  for (const auto& t : walls.triangles) g.wall_point.push_back(walls.points[t[0]] / g.h);
  return g;
}

/// Steps 3 and 4 at one delta: the mesh of psi = max(phi_s - delta, D) and the area of its part off
/// the walls (triangles whose centroid has D < -h / 4) [m^2].
mesh::SurfaceMesh mesh_at(const Fields& g, float delta, double& free_area) {
  const FloatGrid::Ptr psi = g.deep->deepCopy();  // the deep liquid at -band
  {
    auto sa = psi->getAccessor();
    auto pa = g.phi->getConstAccessor();
    auto da = g.wall->getConstAccessor();
    // Every known voxel active, within the band's values; every other voxel is deep liquid (-band)
    // or outside (the background, +band): surface_voxels.hpp.
    const float cap = 0.999f * g.band;
    for (auto it = g.known->cbeginValueOn(); it; ++it) {
      const Coord c = it.getCoord();
      sa.setValue(c, std::clamp(std::max(pa.getValue(c) - delta, da.getValue(c)), -cap, cap));
    }
  }
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*psi, points, triangles, quads, 0.0, 0.0);
  const auto& xf = g.phi->transform();
  mesh::SurfaceMesh m;
  m.vertices.reserve(points.size());
  for (auto& p : points) {
    openvdb::Vec3s q = xf.worldToIndex(p);
    place_on_sharp_edges(g, *psi, delta, q);
    const openvdb::Vec3d w = xf.indexToWorld(q);
    m.vertices.emplace_back(w.x(), w.y(), w.z());
  }
  auto dist2 = [&](int a, int b) { return (m.vertices[a] - m.vertices[b]).squaredNorm(); };
  m.triangles.reserve(triangles.size() + 2 * quads.size());
  for (const auto& t : triangles) m.triangles.push_back({int(t[0]), int(t[1]), int(t[2])});
  for (const auto& q : quads) {
    const int a = q[0], b = q[1], c = q[2], d = q[3];
    if (dist2(a, c) <= dist2(b, d)) {
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    } else {
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({b, c, d});
    }
  }
  free_area = 0;
  const double off_wall = -0.25 * g.h;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d centroid = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0;
    if (wall_distance_at(g, xf.worldToIndex(openvdb::Vec3d(centroid.x(), centroid.y(), centroid.z()))) < off_wall)
      free_area += 0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm();
  }
  return m;
}

double signed_volume(const mesh::SurfaceMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) v += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  return v;
}

}  // namespace

VdbSurface mesh_liquid_voxels(const SurfaceVoxels& voxels, const BoundaryTriangles& walls,
                              const VdbSurfaceOptions& options) {
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  if (!(voxels.voxel_size > 0)) throw std::invalid_argument("mesh_liquid_voxels: voxel size must be positive");
  VdbSurface out;
  bool liquid = false;
  for (std::size_t v = 0; v < voxels.size() && !liquid; ++v) liquid = voxels.inside[v] && voxels.phi[v] < 0;
  if (!liquid) return out;
  const Fields g = grids(voxels, walls);

  // Step 5: secant steps on delta from delta = 0 (the first a Newton step on the free area).
  double free_area = 0;
  auto mesh = [&](double delta) {
    VdbSurface s;
    s.iso_shift = delta;
    s.surface = mesh_at(g, float(delta), free_area);
    s.enclosed_volume = signed_volume(s.surface);
    if (s.enclosed_volume < 0) {  // orient outward, whichever winding volumeToMesh gives
      for (auto& t : s.surface.triangles) std::swap(t[1], t[2]);
      s.enclosed_volume = -s.enclosed_volume;
    }
    ++out.meshings;
    return s;
  };
  VdbSurface best = mesh(0.0);
  const double target = options.target_volume;
  if (target >= 0 && !best.surface.triangles.empty()) {
    const double tol = options.volume_tolerance * target, limit = std::min(options.max_shift, 0.5 * double(g.band));
    double d0 = 0, v0 = best.enclosed_volume;
    double d1 = free_area > 0 ? std::clamp((target - v0) / free_area, -limit, limit) : 0.0;
    for (int k = 1; k < options.max_meshings && std::abs(best.enclosed_volume - target) > tol && d1 != d0; ++k) {
      VdbSurface s = mesh(d1);
      const double v1 = s.enclosed_volume;
      if (std::abs(v1 - target) < std::abs(best.enclosed_volume - target)) best = std::move(s);
      if (v1 == v0) break;
      const double d2 = std::clamp(d1 + (target - v1) * (d1 - d0) / (v1 - v0), -limit, limit);
      d0 = d1;
      v0 = v1;
      d1 = d2;
    }
  }
  best.meshings = out.meshings;
  return best;
}

}  // namespace tetfsi::fluid
