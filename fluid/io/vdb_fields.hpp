#pragma once
/// @file vdb_fields.hpp
/// Internal to vdb_surface.cpp and sharp_edges.cpp (OpenVDB types): the voxel fields of one
/// frame's smooth liquid surface.
#include <Eigen/Core>
#include <vector>

#include <openvdb/openvdb.h>

namespace tetfsi::fluid::vdb {

struct Fields {
  openvdb::FloatGrid::Ptr phi;    ///< phi_s: smoothed level set, continued beyond the fluid [m]
  openvdb::FloatGrid::Ptr wall;   ///< D: signed distance to the boundary near the liquid, clamped to the band [m]
  openvdb::Int32Grid::Ptr nearest;  ///< the boundary triangle nearest each voxel of D's band (-1: none)
  openvdb::MaskGrid::Ptr known;   ///< the voxels where phi_s and D are set
  openvdb::FloatGrid::Ptr deep;   ///< -band at the deep liquid's voxels (SurfaceVoxels::deep), else +band
  std::vector<Eigen::Vector3d> wall_normal;  ///< per boundary triangle: unit normal out of the fluid
  std::vector<Eigen::Vector3d> wall_point;   ///< per boundary triangle: a vertex, index coordinates
  double h = 0;     ///< voxel size [m]
  float band = 0;   ///< narrow band half-width [m]
};

/// Moves the vertex p (index coordinates) that volumeToMesh placed at the mean of the zero
/// crossings of psi = max(phi_s - delta, D) on its cell's edges, when a wall takes part in that
/// cell, to the minimiser of the quadric error sum_i (n_i . (x - p_i))^2 over the crossings p_i
/// with normals n_i (dual contouring of Hermite data, Ju, Losasso, Schaefer & Warren 2002, eq. 1;
/// pseudo-inverse about the mean, singular values below 1/10 of the largest dropped, their
/// section 2.3), kept in the cell. n_i is the normal of the nearest boundary triangle where D is
/// the larger of the two at p_i (the wall), else the gradient of the trilinear phi_s. So a vertex
/// where the free surface meets a wall lies on their line of intersection and one in a corner of
/// walls on the corner: the mesh's edges along walls and corners are not bevelled. Cells that
/// volumeToMesh splits into several vertices (two sheets of surface) keep theirs.
void place_on_sharp_edges(const Fields& fields, const openvdb::FloatGrid& psi, float delta, openvdb::Vec3s& p);

/// D at p (index coordinates), trilinear in its cell [m].
double wall_distance_at(const Fields& fields, const openvdb::Vec3d& p);

}  // namespace tetfsi::fluid::vdb
