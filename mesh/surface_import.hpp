#pragma once
/// @file surface_import.hpp
/// Import of triangle surfaces with assimp (OBJ, PLY, STL, glTF/GLB, FBX, OFF, and whatever else
/// assimp reads) and their placement in the scene.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh {

/// Placement of a model in the scene: x_scene = R * (unit_scale * x_file) + translation.
/// R = Rz(rz) * Ry(ry) * Rx(rx) with rotation_deg = (rx, ry, rz): rotate about the fixed x axis
/// first, then about fixed y, then about fixed z (extrinsic Euler XYZ), angles in degrees.
struct Placement {
  double unit_scale = 1.0;                                   ///< file units -> metres (FBX cm: 0.01)
  Eigen::Vector3d rotation_deg = Eigen::Vector3d::Zero();    ///< (rx, ry, rz) [deg]
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();     ///< [m]
};

/// Rotation matrix of the placement (see Placement).
Eigen::Matrix3d placement_rotation(const Eigen::Vector3d& rotation_deg);

/// Applies the placement to every vertex. Orientation is preserved (R is a rotation and the scale
/// is positive). @throws MeshError if unit_scale <= 0 or a value is not finite
void apply_placement(SurfaceMesh& surface, const Placement& placement);
/// Same on points (e.g. the vertices of a tet mesh, whose orientation it preserves too).
void apply_placement(std::vector<Eigen::Vector3d>& points, const Placement& placement);

/// Largest surface file read [bytes]; bigger files are refused before they are opened.
constexpr std::uintmax_t kMaxSurfaceBytes = std::uintmax_t(1) << 30;

/// Reads every mesh of the file (node transforms applied), keeps its triangles (polygons are
/// triangulated, points and lines dropped), joins vertices at identical positions within and across
/// meshes, then applies the placement. Does not check the surface: call validate_surface().
/// PLY files (recognised by their first line) are read by io::read_ply, every other format by assimp.
/// @throws MeshError naming the file and the cause (missing or non-regular file, over
///         kMaxSurfaceBytes, unreadable format, non-finite coordinates, no triangles)
SurfaceMesh import_surface(const std::string& path, const Placement& placement = {});

}  // namespace tetfsi::mesh
