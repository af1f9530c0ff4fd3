#pragma once
/// @file level_set_voxels.hpp
/// The liquid's nodal level set phi sampled at the voxel centres of a uniform lattice, the input of
/// the render surface (render_surface.hpp, vdb_surface.hpp). Voxel (i, j, k) is centred at
/// x = (i, j, k) h, as in voxel_sampling.hpp (OpenVDB's linear transform of voxel size h). Every
/// voxel centre inside a selected fluid tet T gets the P1 value
///   phi(x) = sum_k lambda_k(x) phi_{n_k},  lambda = barycentric coordinates of x in T,
/// clamped: the field whose zero set the marching-tets surface draws.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::fluid {

/// The sampled voxels, in the order of the tets holding them (each voxel once: a centre on a face
/// shared by two tets goes with the first): deterministic for any thread count.
struct LevelSetVoxels {
  double voxel_size = 0;               ///< h [m]
  std::vector<Eigen::Vector3i> index;  ///< voxel centre at index * h [m]
  std::vector<float> phi;              ///< [m], in [-band, band]
  std::size_t size() const { return index.size(); }
};

/// The tets with a node where phi < band (the liquid and the air within `band` of it).
std::vector<char> liquid_tets(const FluidMesh& mesh, const Eigen::VectorXd& phi, double band);

/// The tets where `values` (one per node) come within `band` of zero: a node below band and one
/// above -band; with `walls`, also those with a node below band and a node on the fluid's boundary
/// (the liquid along its walls, however deep).
std::vector<char> tets_near_zero(const FluidMesh& mesh, const Eigen::VectorXd& values, double band, bool walls);

/// The tets where `values` (one per node) are below `level` at every node.
std::vector<char> tets_below(const FluidMesh& mesh, const Eigen::VectorXd& values, double level);

/// Samples phi (one value per node of `mesh`) at the voxel centres inside the tets marked in `tets`,
/// clamped to [-clamp, clamp] [m].
/// @throws std::invalid_argument if voxel_size or clamp is not positive or phi or tets do not match the mesh
LevelSetVoxels sample_level_set_voxels(const FluidMesh& mesh, const Eigen::VectorXd& phi, double voxel_size,
                                       double clamp, const std::vector<char>& tets);

/// The fluid's boundary faces (walls, open faces, solid interfaces) with a node where phi < band:
/// where the liquid, or the air next to it, meets the end of the fluid. Vertices are the faces'
/// nodes, renumbered in order of first use [m].
struct BoundaryTriangles {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Eigen::Vector3d> normals;  ///< per triangle: unit normal out of the fluid
};
BoundaryTriangles boundary_near_liquid(const FluidMesh& mesh, const Eigen::VectorXd& phi, double band);

/// The mean edge length of the tets that the zero set of phi cuts (a node with phi < 0 and one
/// with phi >= 0), at the given fraction of their distribution (0: the finest cut tet, 0.5: the
/// median, 1: the coarsest) [m]: the size of the marching-tets facets; 0 if no tet is cut.
double cut_tet_edge_length(const FluidMesh& mesh, const Eigen::VectorXd& phi, double fraction);

}  // namespace tetfsi::fluid
