#pragma once
/// @file membrane_shapes.hpp
/// Quad meshes of the membrane shapes a scene can ask for (apps/scene/blocks/mpm.cpp): the
/// primitives rectangle, disc, cylinder, box tube, cushion (closed box surface) and sphere, a
/// triangle surface turned into quads, and the cut by symmetry planes. Every quad is
/// counter-clockwise about its normal; closed shapes have outward normals.
#include <Eigen/Core>

#include <array>
#include <vector>

#include "mesh/surface_mesh.hpp"
#include "solid/membrane/membrane_mesh.hpp"

namespace tetfsi::mpm_setup {

using Vec3 = Eigen::Vector3d;
using membrane::QuadMesh;

/// An axis-aligned symmetry plane x_axis = position; the model keeps the side x_axis >= position.
struct SymmetryPlane {
  int axis = 0;
  double position = 0;
};

/// Two unit vectors e1, e2 with (e1, e2, n) right-handed; e1 = x for n = z.
void tangent_frame(const Vec3& n, Vec3& e1, Vec3& e2);

/// Disc of radius R about `center` with normal n: a square grid of m x m quads (m = 2R / size,
/// rounded, even) mapped onto the disc by the concentric square-to-circle map
/// q = p max(|p1|, |p2|) / |p| (squares of half-side r become circles of radius r).
QuadMesh disc_mesh(const Vec3& center, const Vec3& n, double R, double size);
/// Open tube of radius R from `base` along `axis` (its length is the tube's length), outward
/// normals; a multiple of 4 quads around (nodes on the two planes through the axis along e1, e2).
QuadMesh cylinder_mesh(const Vec3& base, const Vec3& axis, double R, double size);
/// Open tube of rectangular section, half widths (a, b) along the axes (ax + 1) % 3 and (ax + 2) % 3,
/// from `base` (centre of the first section) along axis `ax` for `length`; outward normals. The
/// section is built quadrant by quadrant from the point (a, 0) counter-clockwise, each quadrant
/// from the formulas of the first one mirrored, so that a cut by symmetry planes through the
/// axis leaves the same nodes as a mesh of that quadrant alone.
QuadMesh box_tube_mesh(const Vec3& base, int ax, double a, double b, double length, double size);
/// Closed surface of the box center +- size / 2 (a cushion: two panels joined by a narrow side
/// band when size is small along one axis), outward normals, nodes shared along the edges.
QuadMesh box_surface_mesh(const Vec3& center, const Vec3& size, double element);
/// Closed sphere: the surface of a cube with n x n quads per face (n = (pi/2) R / size, rounded
/// up to even), mapped by the equal-angle map q = tan(pi/4 p) and projected radially.
QuadMesh sphere_mesh(const Vec3& center, double R, double size);
/// Each triangle (a, b, c) becomes three quads (a, m_ab, g, m_ca), (b, m_bc, g, m_ab),
/// (c, m_ca, g, m_bc) with m the edge midpoints (shared by neighbouring triangles) and g the
/// centroid: the same surface and orientation, all quads, node order: vertices, midpoints, centroids.
QuadMesh triangles_to_quads(const mesh::SurfaceMesh& s);
/// Keeps the quads whose four nodes lie on the kept side of every plane (within tol) and the nodes
/// they use, both in their original order.
QuadMesh clip(const QuadMesh& m, const std::vector<SymmetryPlane>& planes, double tol);

/// Node pairs of the edges used by exactly one quad, leaving out edges that lie in a symmetry
/// plane (within tol).
std::vector<std::array<int, 2>> open_edges(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& quads,
                                           const std::vector<SymmetryPlane>& planes, double tol);
/// Number of edges of the mesh used by more than two quads, or used twice in the same direction
/// (inconsistent orientation).
int non_manifold_or_misoriented_edges(const std::vector<std::array<int, 4>>& quads);
/// Volume enclosed by a closed quad surface (each quad as the triangles (0, 1, 2), (0, 2, 3)):
/// V = sum (a - o) . ((b - o) x (c - o)) / 6 with o on every symmetry plane, so the planes close the
/// modelled part (the volume of that part).
double enclosed_volume(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& quads,
                       const std::vector<SymmetryPlane>& planes);

}  // namespace tetfsi::mpm_setup
