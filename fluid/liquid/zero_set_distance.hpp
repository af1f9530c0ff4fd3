#pragma once
/// @file zero_set_distance.hpp
/// Distance from the fluid's nodes to a level set's zero set (its marching-tets triangles), as the
/// redistancing of level_set.hpp needs it: per triangle, the distance continued across the
/// triangle's open edges (ZeroSetDistance), and for every node the nearest triangle found by
/// closest-triangle propagation over the mesh (propagated_distance).
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::fluid {

/// Key of the undirected edge (a, b): the smaller index in the high 32 bits.
inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

/// The distance d_T(x) from x to triangle T of a zero set, with the triangle continued in its plane
/// across each of its open edges (an edge used by this triangle only: where the surface meets a
/// wall or a solid). The surface goes on across the wall, so that a liquid resting against a wall
/// that leans outward (a bowl) keeps a linear phi next to it and the next transfer does not move
/// its waterline (the distance to the cut-off surface grows towards its rim and drains such a
/// layer). The continued distance is taken no smaller than half the distance to the triangle
/// itself (a node that sees the surface edge-on across a thin wall):
///
///     d_T(x) = min( |x - c_T(x)|,  min over open edges e of max( s_e(x), |x - c_T(x)| / 2 ) )
///
/// with c_T(x) the closest point of T and s_e(x) the distance to the half-strip beyond e.
/// Continuous in x, so round-off in phi does not switch a node between the two.
class ZeroSetDistance {
 public:
  explicit ZeroSetDistance(const mesh::SurfaceMesh& surface);
  /// d_T(x) [m] for triangle `triangle` of the surface.
  double operator()(int triangle, const Eigen::Vector3d& x) const;
  /// True if the triangle has an open edge (its distance may be a strip's).
  bool has_open_edge(int triangle) const;

 private:
  const mesh::SurfaceMesh& surface_;
  std::vector<unsigned char> open_;  ///< per triangle: bit e set if its edge (e, e + 1 mod 3) is open
};

/// min over T of d_T(x_i) for every node i, or `reach` where no triangle is nearer [m]: exact for
/// the nodes nearer than `exact_reach`, propagated for the others.
///
/// Closest-triangle propagation (the closest-point transform carried over the mesh, as fast
/// marching carries distances; Tsai 2002, Mauch 2003 for the exact transform it approximates): each
/// node of a tet that holds triangle T starts with d_T; then, nearest node first (Dijkstra order),
/// a node offers its nearest triangle to the nodes that share a tet with it, and each keeps the
/// nearer. The cost is a few distance evaluations per node within `reach`, against a search over
/// every triangle within reach of each node. A node whose nearest triangle is the nearest of none
/// of its neighbours (near the medial axis of two surfaces) gets the distance to a neighbour's,
/// an upper bound that differs from the exact one by far less than an edge (up to 0.15 edge
/// measured where a sheet of liquid breaks up). Nodes nearer than `exact_reach`, whose values move
/// the surface in the next steps, then search every triangle within their propagated distance.
///
/// @param triangle_tet per triangle of `surface`: the fluid tet it lies in (its seeds)
/// @param reach        the distance beyond which nodes are not visited [m] (> 0)
/// @param exact_reach  nodes nearer than this get the exact minimum [m] (0: none)
/// @param kept         per node, 1 where the caller keeps its own value (its distance is then only
///                     carried on, neither searched nor descended); empty: every node is needed
std::vector<double> propagated_distance(const FluidMesh& mesh, const mesh::SurfaceMesh& surface,
                                        const std::vector<int>& triangle_tet, double reach, double exact_reach,
                                        const std::vector<char>& kept = {});

}  // namespace tetfsi::fluid
