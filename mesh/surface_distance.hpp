#pragma once
/// @file surface_distance.hpp
/// Signed distance to a closed triangle surface, for shapes given as surface files (the initial
/// liquid of a free-surface scene, fluid/liquid/level_set.hpp; the walls of a container read from
/// a file as contact obstacles, apps/run/container.hpp).
///
///   d(x) = s(x) min_{y in S} |x - y|,   s(x) = -1 inside S, +1 outside,
///
/// the exact Euclidean distance to the triangles (closest-point queries on a CGAL AABB tree) with the
/// sign of a ray-parity inside test (CGAL::Side_of_triangle_mesh). Points on S have d = 0.
#include <Eigen/Core>
#include <memory>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh {

class SurfaceDistance {
 public:
  /// Builds the search tree of a closed, manifold surface (check it first with validate_surface).
  /// @throws MeshError if the surface has no triangles or CGAL cannot build it (non-manifold input)
  explicit SurfaceDistance(const SurfaceMesh& surface);
  ~SurfaceDistance();
  SurfaceDistance(SurfaceDistance&&) noexcept;
  SurfaceDistance& operator=(SurfaceDistance&&) noexcept;

  /// Signed distance [m] from `x` to the surface, negative inside. Not thread-safe (the inside
  /// test shares one tree); call from one thread.
  double operator()(const Eigen::Vector3d& x) const;
  /// Unsigned distance |d(x)| [m] from `x` to the surface: the closest-point query alone, without
  /// the inside test (for sizing fields, which need no sign). Not thread-safe, as above.
  double unsigned_distance(const Eigen::Vector3d& x) const;
  /// The same, and the point of the surface nearest to x [m] in `closest`.
  double operator()(const Eigen::Vector3d& x, Eigen::Vector3d& closest) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tetfsi::mesh
