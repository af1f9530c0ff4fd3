#pragma once
/// @file solid_geometry.hpp
/// Closed surfaces of the scene's solids: primitives (box, sphere, sheet) generated here, mesh
/// files imported with assimp, then placed (rotation, then translation).
/// TODO(lead): when mesh/ offers its checked surface import and primitives (issue 2 part 4),
/// make surface_of() call those instead of the small versions in this file.
#include <Eigen/Geometry>
#include <filesystem>

#include "apps/scene/scene.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::run {

/// Rotation of Euler angles [deg] applied about x, then y, then z (fixed axes): R = Rz Ry Rx.
Eigen::Matrix3d euler_xyz_deg(const Eigen::Vector3d& deg);

/// Icosphere of `radius` [m] centred at the origin: 20 * 4^subdivisions triangles, outward.
mesh::SurfaceMesh icosphere(double radius, int subdivisions);
/// Axis-aligned box of edge lengths `size` [m] centred at the origin (12 triangles, outward).
mesh::SurfaceMesh box_surface(const Eigen::Vector3d& size);

/// Reads a triangle surface file with assimp, scaled by `unit_scale` [m/unit].
/// @throws InputError naming the file if it cannot be read or is not a closed, manifold surface
mesh::SurfaceMesh import_surface(const std::filesystem::path& file, double unit_scale);

/// The placed rest surface of the solid described by resolved JSON `solid` (/solids/i).
mesh::SurfaceMesh surface_of(const scene::Json& solid);

/// Enclosed volume [m^3] of a closed, outward-oriented surface (divergence theorem).
double enclosed_volume(const mesh::SurfaceMesh& s);

}  // namespace tetfsi::run
