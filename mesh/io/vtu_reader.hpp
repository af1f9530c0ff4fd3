#pragma once
/// @file vtu_reader.hpp
/// Reader for VTK XML unstructured grids (.vtu), the counterpart of vtu_writer.hpp.
///
/// Supported (docs.vtk.org "VTK XML file formats"): DataArrays with format="ascii", inline
/// format="binary" (base64 of a byte-count header followed by the payload, header and payload
/// base64-encoded together as our uncompressed writer does or separately as VTK does) and
/// format="appended" into <AppendedData encoding="raw"> (what our zlib writer and ParaView
/// write); uncompressed or compressor="vtkZLibDataCompressor" (zlib_blocks.hpp); header_type
/// UInt32 or UInt64; types Int8..Int64, UInt8..UInt64, Float32, Float64, little endian. Not
/// supported, with a clear error: other compressors (LZ4, LZMA), base64-encoded appended data,
/// big-endian files.
/// Hand-written for the same reason as the writer: the VTK C++ libraries are a 700 MB dependency.
#include <filesystem>
#include <string>

#include "mesh/hex_mesh.hpp"
#include "mesh/io/vtu_writer.hpp"

namespace tetfsi::mesh::io {

/// Reads points, cells and all point/cell fields (converted to double) of a .vtu file.
/// @throws std::runtime_error naming the file and the cause (missing file, malformed XML, wrong
///         sizes, unsupported encoding)
UnstructuredGrid read_vtu(const std::filesystem::path& path);
/// Same from the file's text (`name` is used in error messages).
UnstructuredGrid parse_vtu(const std::string& text, const std::string& name = "<string>");

/// Reads a hexahedral mesh: every cell must be a VTK_HEXAHEDRON (type 12).
/// @throws std::runtime_error as read_vtu, or naming the first cell of another type
HexMesh read_hex_mesh_vtu(const std::filesystem::path& path);
/// Converts a grid of hexahedra to a HexMesh (throws std::runtime_error for other cell types).
HexMesh to_hex_mesh(const UnstructuredGrid& grid, const std::string& name = "<grid>");

}  // namespace tetfsi::mesh::io
