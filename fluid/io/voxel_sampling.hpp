#pragma once
/// @file voxel_sampling.hpp
/// The fluid's node fields sampled at the centres of a uniform voxel lattice, for volume files
/// (vdb_writer.hpp). Voxel (i, j, k) is the cube of edge h centred at x = (i, j, k) h (OpenVDB's
/// linear transform of voxel size h: index space scaled by h). Every voxel whose centre lies in a
/// fluid tet T is sampled with the P1 interpolant of the node values,
///   f(x) = sum_k lambda_k(x) f_{n_k},  lambda = barycentric coordinates of x in T,
/// the same continuous field that the .vtu point data draws in ParaView; voxels whose centre lies
/// outside the fluid (beyond its boundary or inside a solid) are not listed.
#include <Eigen/Core>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"

namespace tetfsi::fluid {

/// Node values to sample (fluid::average_to_nodes of the per-tet fields, as fluid_output.hpp's
/// point data).
struct NodalFields {
  Eigen::VectorXd smoke;        ///< [-]
  Eigen::VectorXd temperature;  ///< [K]
  TetVectors velocity;          ///< [m/s]
};

/// The sampled voxels, in lattice order (k, then j, then i ascending): deterministic.
struct VoxelSamples {
  double voxel_size = 0;                  ///< h [m]
  std::vector<Eigen::Vector3i> index;     ///< voxel centre at index * h [m]
  std::vector<float> smoke, temperature;  ///< [-], [K]
  std::vector<Eigen::Vector3f> velocity;  ///< [m/s]
  std::size_t size() const { return index.size(); }
};

/// Lattice index range of the voxels covering the box [lo, hi]: floor(lo / h) .. ceil(hi / h) (one
/// more on a side than the centres strictly inside, so that a centre on the box's face within
/// round-off, e.g. 48 x 0.025 = 1.2000000000000002 on a face at 1.2, is left to the locator).
struct VoxelRange {
  Eigen::Vector3i first, last;
  /// Number of voxel centres in the range (as a double: a too-fine h overflows int).
  double count() const;
};
VoxelRange voxel_range(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double voxel_size);

/// Bounding box of the mesh's nodes, as voxel_range.
VoxelRange voxel_range(const FluidMesh& mesh, double voxel_size);

/// Samples `nodal` on `mesh` (node positions and geometry of the frame) at the voxel centres of
/// voxel_range(mesh, voxel_size) that the PointLocator finds inside the fluid. Rows of voxels run in
/// parallel, each walking from its previous voxel's tet; the result does not depend on the
/// thread count.
VoxelSamples sample_voxels(const FluidMesh& mesh, const NodalFields& nodal, double voxel_size);

}  // namespace tetfsi::fluid
