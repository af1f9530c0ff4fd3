#pragma once
/// @file surface_face.hpp
/// Boundary faces of a solid mesh (3-node triangles of tets, 4-node bilinear quads of hexes) and
/// their quadrature in the reference square / triangle, for surface loads.
///
/// A face is 4 node indices, the last -1 for a triangle; nodes are ordered so that the normal
/// (right-hand rule) points out of the body. Parametrisation x(s, t) = sum_a N_a(s, t) x_a:
///  - triangle: N = (1 - s - t, s, t) on s, t >= 0, s + t <= 1; 3-point rule at the edge
///    midpoints (weights 1/6 each, exact for quadratic integrands);
///  - quad: N_a = (1 + s_a s)(1 + t_a t)/4 on [-1, 1]^2; 2 x 2 Gauss rule (weights 1).
/// The area vector of a quadrature point is (dx/ds x dx/dt) w, so sum over points of
/// N_a (dx/ds x dx/dt) w = int_face N_a n dA.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace tetfsi::solid {

using SurfaceFace = std::array<int, 4>;  ///< node indices, [3] = -1 for a triangle

inline int face_node_count(const SurfaceFace& f) { return f[3] < 0 ? 3 : 4; }

/// One quadrature point of a face: shape values, their s and t derivatives, weight.
struct FacePoint {
  Eigen::Vector4d N = Eigen::Vector4d::Zero(), dNds = Eigen::Vector4d::Zero(), dNdt = Eigen::Vector4d::Zero();
  double weight = 0.0;
};

/// The quadrature points of a triangle (3) or quad (4) face (see the file comment).
const std::vector<FacePoint>& face_points(const SurfaceFace& face);

/// Calls fn(point, x, dx/ds x dx/dt) at every quadrature point of `face` with node positions
/// `position(node)` (reference or current).
template <class Position, class Fn>
void for_each_face_point(const SurfaceFace& face, Position&& position, Fn&& fn) {
  const int n = face_node_count(face);
  for (const FacePoint& p : face_points(face)) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero(), xs = Eigen::Vector3d::Zero(), xt = Eigen::Vector3d::Zero();
    for (int a = 0; a < n; ++a) {
      const Eigen::Vector3d xa = position(face[a]);
      x += p.N(a) * xa;
      xs += p.dNds(a) * xa;
      xt += p.dNdt(a) * xa;
    }
    fn(p, x, xs, xt);
  }
}

/// Boundary triangles (faces of exactly one tet) of a positively oriented tet mesh, outward,
/// as SurfaceFaces; in a fixed order (sorted by their node sets).
std::vector<SurfaceFace> tet_boundary_faces(const std::vector<std::array<int, 4>>& tets);

/// Faces of `faces` whose nodes all lie in [lo - tol, hi + tol] (positions `vertices`).
std::vector<SurfaceFace> faces_in_box(const std::vector<SurfaceFace>& faces,
                                      const std::vector<Eigen::Vector3d>& vertices, const Eigen::Vector3d& lo,
                                      const Eigen::Vector3d& hi, double tol);

/// Nodes whose position lies in [lo - tol, hi + tol], ascending.
std::vector<int> vertices_in_box(const std::vector<Eigen::Vector3d>& vertices, const Eigen::Vector3d& lo,
                                 const Eigen::Vector3d& hi, double tol);

}  // namespace tetfsi::solid
