#pragma once
/// @file vdb_writer.hpp
/// OpenVDB volume files of the fluid (Debian libopenvdb-dev, OpenVDB 10; Museth 2013, "VDB:
/// High-resolution sparse volumes with dynamic topology", ACM TOG 32(3)). The only translation
/// unit that includes OpenVDB: this interface holds no OpenVDB type.
///
/// A file holds, on the linear transform of voxel size h (voxel (i, j, k) centred at (i, j, k) h,
/// world coordinates in metres), the grids
///   - `density` (float, fog volume): smoke concentration [-],
///   - `temperature` (float): [K],
///   - `velocity` (Vec3f, world space, contravariant-relative): [m/s],
/// active at the sampled voxels (voxel_sampling.hpp), background 0 elsewhere; constant blocks are
/// pruned to tiles (lossless); and, given a closed liquid surface, `surface` (float, level set):
/// the signed distance [m] to it (negative inside) in a narrow band of 3 voxels on each side
/// (openvdb::tools::meshToLevelSet), background +-3 h.
/// Values are compressed with zlib (COMPRESS_ZIP | COMPRESS_ACTIVE_MASK, read by every OpenVDB
/// build). The file's UUID, random in OpenVDB, is replaced by one hashed from the file's content
/// so that the same frame gives the same bytes.
#include <cstdint>
#include <filesystem>

#include "fluid/io/voxel_sampling.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::fluid {

/// Writes `samples` (and `surface`, if not null: a closed, consistently oriented triangle mesh in
/// the same coordinates) to `path` atomically (a temporary file renamed over it). Returns the
/// file's size [bytes]. @throws std::runtime_error naming the path if it cannot be written
std::uintmax_t write_vdb(const std::filesystem::path& path, const VoxelSamples& samples,
                         const mesh::SurfaceMesh* surface);

}  // namespace tetfsi::fluid
