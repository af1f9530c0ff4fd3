#pragma once
/// @file vtu_writer.hpp
/// VTK XML unstructured-grid (.vtu) and collection (.pvd) writers for ParaView.
/// Points are Float64, connectivity and offsets Int64, types UInt8; the fields Float64 or
/// Float32 (VtuPrecision).
///
/// Format: docs.vtk.org "VTK XML file formats", header_type="UInt64". Two encodings of the data
/// arrays, both read by ParaView and VTK's XMLUnstructuredGridReader:
///   - VtuCompression::Zlib (the default): compressor="vtkZLibDataCompressor", every array
///     zlib-compressed in 32 KiB blocks with VTK's block header (zlib_blocks.hpp) and stored raw in
///     an <AppendedData encoding="raw"> section (no base64: 3/4 of the bytes).
///   - VtuCompression::None: inline base64 "binary" with a UInt64 byte-count header.
/// Written by hand because libvtk9-dev pulls in 700 MB of packages for what is a few hundred lines
/// of XML; zlib does the compression.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "mesh/surface_mesh.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh::io {

/// VTK cell type ids used by tetfsi.
enum class VtkCell : std::uint8_t {
  Vertex = 1,
  Triangle = 5,
  Quad = 9,
  Tetra = 10,
  Hexahedron = 12,
};

/// A named field: `components` values per point (or per cell), stored point after point.
struct DataArray {
  std::string name;
  int components = 1;
  std::vector<double> values;  ///< size = components * count
};

/// An unstructured grid in VTK's layout: cells given by flat connectivity and offsets.
struct UnstructuredGrid {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int64_t> connectivity;  ///< point indices of all cells, concatenated
  std::vector<std::int64_t> offsets;       ///< end of each cell in `connectivity`
  std::vector<std::uint8_t> types;         ///< VtkCell of each cell
  std::vector<DataArray> point_data;
  std::vector<DataArray> cell_data;

  int num_points() const { return static_cast<int>(points.size()); }
  int num_cells() const { return static_cast<int>(types.size()); }

  /// Appends one cell of the given type and point indices.
  template <class Indices>
  void add_cell(VtkCell type, const Indices& ids) {
    for (auto i : ids) connectivity.push_back(static_cast<std::int64_t>(i));
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(static_cast<std::uint8_t>(type));
  }
  /// Adds a point field; throws std::invalid_argument if its size does not match.
  void add_point_data(std::string name, int components, std::vector<double> values);
  /// Adds a cell field; throws std::invalid_argument if its size does not match.
  void add_cell_data(std::string name, int components, std::vector<double> values);
};

/// Grid of a tet mesh, with the subdomain labels as the cell field "subdomain" when present.
UnstructuredGrid make_grid(const TetMesh& mesh);
/// Grid of a hex mesh (VTK_HEXAHEDRON cells).
UnstructuredGrid make_grid(const HexMesh& mesh);
/// Grid of a triangle surface.
UnstructuredGrid make_grid(const SurfaceMesh& mesh);
/// Point cloud: one VTK_VERTEX cell per point (MPM particles).
UnstructuredGrid make_point_cloud(const std::vector<Eigen::Vector3d>& points);

/// How write_vtu stores the data arrays (scene key export.compression).
enum class VtuCompression { None, Zlib };

/// Type of the stored point and cell fields (scene key export.precision); the points and the
/// cells are always stored exactly (Float64 coordinates, Int64 indices).
///   - Float64: the doubles as they are (lossless).
///   - Float32: each value rounded to the nearest float (relative error <= 2^-24 = 6.0e-8); a
///     finite value beyond the float range is stored as +-FLT_MAX (3.4e38), NaN and +-inf stay
///     what they are, magnitudes below the smallest float subnormal (1.4e-45) become +-0.
enum class VtuPrecision { Float64, Float32 };

/// The value a Float32 field stores for `v` (see VtuPrecision::Float32).
float to_vtu_float(double v);

/// Writes `grid` as a .vtu file, atomically (see atomic_file.hpp); the one writer of .vtu files.
/// @return the size of the file [bytes]
/// @throws std::runtime_error on I/O failure, std::invalid_argument on inconsistent sizes
std::uintmax_t write_vtu(const std::filesystem::path& path, const UnstructuredGrid& grid,
                         VtuCompression compression = VtuCompression::Zlib,
                         VtuPrecision fields = VtuPrecision::Float64);

/// A ParaView collection (.pvd) indexing one file per frame by its physical time [s].
/// Each call to add() rewrites the .pvd atomically, so it always lists whole frames only.
class PvdCollection {
 public:
  explicit PvdCollection(std::filesystem::path pvd_path);
  /// Records `file` (a path relative to the .pvd's folder) at time `time` and rewrites the .pvd.
  void add(double time, const std::string& file);
  const std::filesystem::path& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }

 private:
  std::filesystem::path path_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace tetfsi::mesh::io
