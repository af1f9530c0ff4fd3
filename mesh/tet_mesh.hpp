#pragma once
/// @file tet_mesh.hpp
/// Plain-array tetrahedral mesh shared by every module (no CGAL types cross this header).
///
/// Conventions:
///  - Units: metres.
///  - Every tet is positively oriented: det[x1 - x0, x2 - x0, x3 - x0] > 0.
///  - `subdomain[t]` labels tet t: `kFluidSubdomain` (1) for fluid, `solid_subdomain(i)` (2 + i)
///    for the i-th solid of the scene, as in the CGAL Mesh_3 complex.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace tetfsi::mesh {

constexpr int kFluidSubdomain = 1;
/// Subdomain label of the i-th solid (0-based) of a scene.
constexpr int solid_subdomain(int solid_index) { return 2 + solid_index; }

struct TetMesh {
  std::vector<Eigen::Vector3d> vertices;    ///< #V positions [m]
  std::vector<std::array<int, 4>> tets;     ///< #T vertex indices, positively oriented
  std::vector<int> subdomain;               ///< #T labels (empty means: all one subdomain)

  int num_vertices() const { return static_cast<int>(vertices.size()); }
  int num_tets() const { return static_cast<int>(tets.size()); }
};

/// Signed volume of the tet (a, b, c, d): det[b - a, c - a, d - a] / 6.
inline double signed_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

/// Signed volume of tet t of `mesh`.
inline double signed_volume(const TetMesh& mesh, int t) {
  const auto& v = mesh.tets[t];
  return signed_volume(mesh.vertices[v[0]], mesh.vertices[v[1]], mesh.vertices[v[2]],
                       mesh.vertices[v[3]]);
}

}  // namespace tetfsi::mesh
