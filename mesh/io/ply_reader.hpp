#pragma once
/// @file ply_reader.hpp
/// Reader of PLY surfaces (Turk 1994 "The PLY polygon file format": ASCII, binary little- and
/// big-endian). Hand-written because assimp 5.2's PLY reader loops forever on a file that stops
/// after its header and aborts the process (an assert in its triangulation) on a file cut inside
/// its vertex list; this one checks every count, type, list length and index against the bytes
/// actually present before using it, so a malformed file ends in a MeshError naming the file.
#include <string>
#include <string_view>

#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh::io {

/// Largest PLY file read [bytes]; bigger files are refused before they are read.
constexpr std::size_t kMaxPlyBytes = std::size_t(1) << 30;

/// Parses PLY content: positions x, y, z of element `vertex`, polygons of the list property
/// `vertex_indices` (or `vertex_index`) of element `face`, split into triangle fans. Other
/// elements and properties are read and skipped.
/// @param name  used in messages (the file name)
/// @throws MeshError "<name>: PLY ...: <defect>" on any malformed, cut or inconsistent content,
///         non-finite coordinates, faces with fewer than 3 or out-of-range indices, or no face
SurfaceMesh parse_ply(std::string_view content, const std::string& name);

/// Reads a PLY file (a regular file of at most kMaxPlyBytes) with parse_ply.
/// @throws MeshError naming the file
SurfaceMesh read_ply(const std::string& path);

}  // namespace tetfsi::mesh::io
