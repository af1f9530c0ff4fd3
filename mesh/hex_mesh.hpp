#pragma once
/// @file hex_mesh.hpp
/// Plain-array 8-node hexahedral mesh (Total Lagrangian solids).
/// Node order is VTK_HEXAHEDRON's: bottom face (0,1,2,3) counter-clockwise seen from above
/// (+z), then the top face (4,5,6,7) above nodes 0..3.
#include <Eigen/Core>
#include <array>
#include <vector>

namespace tetfsi::mesh {

/// Local node indices of the 6 faces of a VTK hexahedron, ordered so that their normals (right-hand
/// rule) point out of the element.
inline constexpr int kHexFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                        {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

/// The three edge neighbours of each corner of a VTK hexahedron, ordered so that
/// det[x_a - x_i, x_b - x_i, x_c - x_i] > 0 at every corner i of a positively oriented element
/// (the sign of the trilinear map's Jacobian at that corner).
inline constexpr int kHexCornerNeighbours[8][3] = {{1, 3, 4}, {2, 0, 5}, {3, 1, 6}, {0, 2, 7},
                                                   {7, 5, 0}, {4, 6, 1}, {5, 7, 2}, {6, 4, 3}};

/// det(dX/dxi) of the trilinear map X(xi) = sum_a N_a(xi) x_a of a hex with corners x (VTK order)
/// at the natural point xi in [-1, 1]^3; N_a = (1 + xi_a xi)(1 + eta_a eta)(1 + zeta_a zeta) / 8.
/// A cube of edge l has (l/2)^3 everywhere; > 0 for a positively oriented element.
inline double hex_jacobian_determinant(const std::array<Eigen::Vector3d, 8>& x, const Eigen::Vector3d& xi) {
  static constexpr double s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                     {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();  // columns dX/dxi, dX/deta, dX/dzeta
  for (int a = 0; a < 8; ++a) {
    const Eigen::Vector3d f(1 + s[a][0] * xi.x(), 1 + s[a][1] * xi.y(), 1 + s[a][2] * xi.z());
    J.col(0) += 0.125 * s[a][0] * f.y() * f.z() * x[a];
    J.col(1) += 0.125 * s[a][1] * f.x() * f.z() * x[a];
    J.col(2) += 0.125 * s[a][2] * f.x() * f.y() * x[a];
  }
  return J.determinant();
}

struct HexMesh {
  std::vector<Eigen::Vector3d> vertices;   ///< #V reference positions [m]
  std::vector<std::array<int, 8>> hexes;   ///< #H vertex indices, VTK order

  int num_vertices() const { return static_cast<int>(vertices.size()); }
  int num_hexes() const { return static_cast<int>(hexes.size()); }
};

}  // namespace tetfsi::mesh
