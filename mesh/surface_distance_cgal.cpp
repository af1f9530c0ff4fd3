/// @file surface_distance_cgal.cpp
/// CGAL translation unit of surface_distance.hpp (AABB tree + Side_of_triangle_mesh). Kept apart so
/// that no other file pays for the CGAL headers.
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <string>
#include <vector>

#include "mesh/surface_distance.hpp"

namespace tetfsi::mesh {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<K::Point_3>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<CgalMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
using Inside = CGAL::Side_of_triangle_mesh<CgalMesh, K>;
}  // namespace

struct SurfaceDistance::Impl {
  CgalMesh mesh;
  Tree tree;
  std::unique_ptr<Inside> inside;
};

SurfaceDistance::SurfaceDistance(const SurfaceMesh& surface) : impl_(std::make_unique<Impl>()) {
  if (surface.triangles.empty()) throw MeshError("signed distance: the surface has no triangles");
  std::vector<CgalMesh::Vertex_index> v;
  v.reserve(surface.vertices.size());
  for (const auto& p : surface.vertices) v.push_back(impl_->mesh.add_vertex(K::Point_3(p.x(), p.y(), p.z())));
  for (std::size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    if (impl_->mesh.add_face(v[t[0]], v[t[1]], v[t[2]]) == CgalMesh::null_face())
      throw MeshError("signed distance: CGAL could not add triangle " + std::to_string(f) + " (non-manifold input)");
  }
  impl_->tree.insert(faces(impl_->mesh).first, faces(impl_->mesh).second, impl_->mesh);
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
  impl_->inside = std::make_unique<Inside>(impl_->tree);
}

SurfaceDistance::~SurfaceDistance() = default;
SurfaceDistance::SurfaceDistance(SurfaceDistance&&) noexcept = default;
SurfaceDistance& SurfaceDistance::operator=(SurfaceDistance&&) noexcept = default;

double SurfaceDistance::operator()(const Eigen::Vector3d& x, Eigen::Vector3d& closest) const {
  const K::Point_3 p(x.x(), x.y(), x.z());
  const K::Point_3 y = impl_->tree.closest_point(p);
  closest = Eigen::Vector3d(y.x(), y.y(), y.z());
  const double d = (x - closest).norm();
  const auto side = (*impl_->inside)(p);
  if (side == CGAL::ON_BOUNDARY) return 0.0;
  return side == CGAL::ON_BOUNDED_SIDE ? -d : d;
}

double SurfaceDistance::unsigned_distance(const Eigen::Vector3d& x) const {
  return std::sqrt(CGAL::to_double(impl_->tree.squared_distance(K::Point_3(x.x(), x.y(), x.z()))));
}

double SurfaceDistance::operator()(const Eigen::Vector3d& x) const {
  const K::Point_3 p(x.x(), x.y(), x.z());
  const double d = unsigned_distance(x);
  const auto side = (*impl_->inside)(p);
  if (side == CGAL::ON_BOUNDARY) return 0.0;
  return side == CGAL::ON_BOUNDED_SIDE ? -d : d;
}

}  // namespace tetfsi::mesh
