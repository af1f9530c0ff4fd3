#pragma once
/// @file point_locator.hpp
/// Point location in a FluidMesh: a walk through tet adjacency from a hint tet, towards the face
/// with the most negative barycentric coordinate (visibility walk), and, when the walk hits the
/// fluid boundary (non-convex domains: holes, solids) or exceeds its step budget, a uniform grid
/// whose cells list every tet whose bounding box overlaps them. The grid is complete (a tet that
/// contains x overlaps x's cell), so "not found" means x is outside the fluid; such a point is
/// taken to the nearest point of the fluid's boundary faces (searched in rings of grid cells).
///
/// Why the nearest point: a back-trace that leaves the fluid through a wall (a level-set node on a
/// slip wall whose node-averaged velocity has a part across it) must read the value at the wall
/// where the fluid came from, which for a plane wall is the trace with only its tangential part.
/// The location used before, the walk's last tet with its negative barycentric coordinates set to
/// 0, is the central projection from a vertex of whichever boundary tet the walk ended in: it moves
/// the point along the wall by up to the distance it lies outside, in a direction set by where the
/// walk started. The walks of a node's traces start in its lowest-numbered tet, and the numbering
/// follows a space-filling curve from the low corner of the box, so on the low-coordinate side wall
/// of a sloshing tank the feet landed lower than on the opposite wall, the contact line there
/// crept up, and a tongue of liquid climbed that wall alone (fluid/README.md, "Liquids").
#include <Eigen/Core>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::fluid {

/// A located point: its tet and barycentric coordinates. A point outside the fluid is located at
/// the point of the fluid's boundary nearest to it (inside = false; its barycentric coordinates are
/// >= 0 in the tet of that boundary face).
struct Location {
  int tet = -1;
  Eigen::Vector4d bary = Eigen::Vector4d::Constant(0.25);
  bool inside = false;  ///< false: x is outside the fluid, and the location is its nearest boundary point
};

class PointLocator {
 public:
  /// Builds the grid (about one cell per eight tets over the bounding box). The mesh must outlive this.
  explicit PointLocator(const FluidMesh& mesh);

  /// Locates x, walking from `hint` (a fluid tet, or -1 to start from the grid).
  Location locate(const Eigen::Vector3d& x, int hint) const;

  /// Barycentric coordinates of x with respect to tet t (may be negative outside t).
  Eigen::Vector4d barycentric(int t, const Eigen::Vector3d& x) const;

  /// The mesh this locator searches.
  const FluidMesh& mesh() const { return mesh_; }

 private:
  int grid_find(const Eigen::Vector3d& x) const;   ///< containing tet or -1
  /// The point of the fluid's boundary faces nearest to x, located in the tet of its face
  /// (deterministic: the first nearest face in the cells' order).
  Location nearest_on_boundary(const Eigen::Vector3d& x) const;
  int grid_nearest_tet(const Eigen::Vector3d& x) const;  ///< some tet from the nearest non-empty cell
  Eigen::Vector3i cell_of(const Eigen::Vector3d& x) const;

  const FluidMesh& mesh_;
  Eigen::Vector3d lo_, cell_size_;
  Eigen::Vector3i dims_;
  std::vector<int> cell_start_;  ///< CSR over cells
  std::vector<int> cell_tets_;
  /// Per tet: bounding box grown by 1e-6 of its largest extent, rounded outwards to single
  /// precision. A point outside it has a barycentric coordinate far below -kInsideTolerance, so
  /// grid_find skips the tet without changing which tet it returns (a failed search scans a whole cell).
  std::vector<Eigen::Vector3f> box_lo_, box_hi_;
};

}  // namespace tetfsi::fluid
