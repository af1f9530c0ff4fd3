#pragma once
/// @file ply_writer.hpp
/// Triangle surfaces as binary little-endian PLY (paulbourke.net/dataformats/ply), the format
/// Blender and Houdini import as per-frame sequences. Optional per-vertex velocity is written as
/// the vertex properties vx, vy, vz (motion blur). Positions and velocities are float32, faces
/// are `list uchar int vertex_indices`.
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh::io {

/// Writes `surface` as a binary little-endian PLY file, atomically (atomic_file.hpp).
/// @param velocity  empty, or one velocity [m/s] per vertex
/// @throws std::invalid_argument if velocity has the wrong size, std::runtime_error on I/O failure
void write_ply(const std::filesystem::path& path, const SurfaceMesh& surface,
               const std::vector<Eigen::Vector3d>& velocity = {});

}  // namespace tetfsi::mesh::io
