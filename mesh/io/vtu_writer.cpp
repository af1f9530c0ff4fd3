#include "mesh/io/vtu_writer.hpp"

#include <cfloat>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "mesh/io/atomic_file.hpp"
#include "mesh/io/zlib_blocks.hpp"

namespace tetfsi::mesh::io {
namespace {

// Base64 (RFC 4648) of a byte buffer. Hand-written: no Debian-packaged C++ library offers it
// without pulling in a large dependency, and VTK's inline binary format requires it.
std::string base64(const unsigned char* data, std::size_t n) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve(4 * ((n + 2) / 3));
  std::size_t i = 0;
  for (; i + 2 < n; i += 3) {
    const unsigned v = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  if (i < n) {
    unsigned v = data[i] << 16;
    if (i + 1 < n) v |= data[i + 1] << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += (i + 1 < n) ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// Bytes of an array as stored in memory (little endian on the machines tetfsi runs on).
template <class T>
const unsigned char* bytes_of(const std::vector<T>& values) {
  return reinterpret_cast<const unsigned char*>(values.data());
}

const char* vtk_type_name(double) { return "Float64"; }
const char* vtk_type_name(float) { return "Float32"; }
const char* vtk_type_name(std::int64_t) { return "Int64"; }
const char* vtk_type_name(std::uint8_t) { return "UInt8"; }

// Writes the DataArrays of one file. Uncompressed: inline base64 of a UInt64 byte count followed
// by the payload, encoded together. zlib: an empty DataArray element pointing (offset) into the
// raw appended section, which holds the compression header and blocks (zlib_blocks.hpp).
class ArrayWriter {
 public:
  ArrayWriter(std::ostream& out, VtuCompression compression) : out_(out), compression_(compression) {}

  template <class T>
  void write(const std::string& name, int components, const std::vector<T>& values) {
    const std::uint64_t n = values.size() * sizeof(T);
    out_ << "        <DataArray type=\"" << vtk_type_name(T{}) << "\" Name=\"" << name
         << "\" NumberOfComponents=\"" << components << "\"";
    if (compression_ == VtuCompression::Zlib) {
      out_ << " format=\"appended\" offset=\"" << appended_.size() << "\"/>\n";
      append_zlib_blocks(bytes_of(values), n, appended_,
                         std::is_floating_point_v<T> ? ZlibStrategy::RleOrStored : ZlibStrategy::Default);
      return;
    }
    std::vector<unsigned char> buffer(sizeof(n) + n);
    std::memcpy(buffer.data(), &n, sizeof(n));
    if (n) std::memcpy(buffer.data() + sizeof(n), values.data(), n);
    out_ << " format=\"binary\">\n          " << base64(buffer.data(), buffer.size()) << "\n        </DataArray>\n";
  }

  /// A field, stored as `precision` says.
  void write_field(const DataArray& a, VtuPrecision precision) {
    if (precision == VtuPrecision::Float64) return write(a.name, a.components, a.values);
    std::vector<float> rounded(a.values.size());
    for (std::size_t i = 0; i < rounded.size(); ++i) rounded[i] = to_vtu_float(a.values[i]);
    write(a.name, a.components, rounded);
  }

  /// The <AppendedData> section (nothing when uncompressed); call once, after the last array.
  void finish() {
    if (compression_ != VtuCompression::Zlib) return;
    out_ << "  <AppendedData encoding=\"raw\">\n   _";
    out_.write(appended_.data(), static_cast<std::streamsize>(appended_.size()));
    out_ << "\n  </AppendedData>\n";
  }

 private:
  std::ostream& out_;
  VtuCompression compression_;
  std::string appended_;
};

void check_field(const DataArray& a, std::size_t count, const char* where) {
  if (a.components < 1 || a.values.size() != count * static_cast<std::size_t>(a.components)) {
    throw std::invalid_argument(std::string(where) + " field '" + a.name + "' has " +
                                std::to_string(a.values.size()) + " values, expected " +
                                std::to_string(count) + " x " + std::to_string(a.components));
  }
}

}  // namespace

float to_vtu_float(double v) {
  // A finite double beyond the float range has no float value (converting it is undefined
  // behaviour); NaN and +-inf convert to themselves.
  if (std::isfinite(v) && std::abs(v) > FLT_MAX) return v > 0 ? FLT_MAX : -FLT_MAX;
  return static_cast<float>(v);
}

void UnstructuredGrid::add_point_data(std::string name, int components, std::vector<double> values) {
  DataArray a{std::move(name), components, std::move(values)};
  check_field(a, points.size(), "point");
  point_data.push_back(std::move(a));
}

void UnstructuredGrid::add_cell_data(std::string name, int components, std::vector<double> values) {
  DataArray a{std::move(name), components, std::move(values)};
  check_field(a, types.size(), "cell");
  cell_data.push_back(std::move(a));
}

UnstructuredGrid make_grid(const TetMesh& mesh) {
  UnstructuredGrid g;
  g.points = mesh.vertices;
  for (const auto& t : mesh.tets) g.add_cell(VtkCell::Tetra, t);
  if (!mesh.subdomain.empty()) {
    g.add_cell_data("subdomain", 1, std::vector<double>(mesh.subdomain.begin(), mesh.subdomain.end()));
  }
  return g;
}

UnstructuredGrid make_grid(const HexMesh& mesh) {
  UnstructuredGrid g;
  g.points = mesh.vertices;
  for (const auto& h : mesh.hexes) g.add_cell(VtkCell::Hexahedron, h);
  return g;
}

UnstructuredGrid make_grid(const SurfaceMesh& mesh) {
  UnstructuredGrid g;
  g.points = mesh.vertices;
  for (const auto& f : mesh.triangles) g.add_cell(VtkCell::Triangle, f);
  return g;
}

UnstructuredGrid make_point_cloud(const std::vector<Eigen::Vector3d>& points) {
  UnstructuredGrid g;
  g.points = points;
  for (std::size_t i = 0; i < points.size(); ++i) g.add_cell(VtkCell::Vertex, std::array<std::size_t, 1>{i});
  return g;
}

std::uintmax_t write_vtu(const std::filesystem::path& path, const UnstructuredGrid& grid, VtuCompression compression,
                         VtuPrecision fields) {
  if (grid.offsets.size() != grid.types.size()) {
    throw std::invalid_argument("write_vtu: offsets and types differ in length");
  }
  for (const auto& a : grid.point_data) check_field(a, grid.points.size(), "point");
  for (const auto& a : grid.cell_data) check_field(a, grid.types.size(), "cell");
  for (auto c : grid.connectivity) {
    if (c < 0 || c >= grid.num_points()) {
      throw std::invalid_argument("write_vtu: cell refers to point " + std::to_string(c) +
                                  " of " + std::to_string(grid.num_points()));
    }
  }
  std::uintmax_t written = 0;
  write_file_atomically(path, [&](std::ostream& out) {
    const auto start = out.tellp();
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\""
        << (compression == VtuCompression::Zlib ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << grid.num_points() << "\" NumberOfCells=\""
        << grid.num_cells() << "\">\n";
    ArrayWriter arrays(out, compression);
    out << "      <PointData>\n";
    for (const auto& a : grid.point_data) arrays.write_field(a, fields);
    out << "      </PointData>\n      <CellData>\n";
    for (const auto& a : grid.cell_data) arrays.write_field(a, fields);
    out << "      </CellData>\n      <Points>\n";
    std::vector<double> xyz;
    xyz.reserve(3 * grid.points.size());
    for (const auto& p : grid.points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    arrays.write("Points", 3, xyz);
    out << "      </Points>\n      <Cells>\n";
    arrays.write("connectivity", 1, grid.connectivity);
    arrays.write("offsets", 1, grid.offsets);
    arrays.write("types", 1, grid.types);
    out << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
    arrays.finish();
    out << "</VTKFile>\n";
    written = static_cast<std::uintmax_t>(out.tellp() - start);
  });
  return written;
}

PvdCollection::PvdCollection(std::filesystem::path pvd_path) : path_(std::move(pvd_path)) {}

void PvdCollection::add(double time, const std::string& file) {
  entries_.emplace_back(time, file);
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
  out << std::setprecision(17);
  for (const auto& [t, f] : entries_) {
    out << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << f << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  write_file_atomically(path_, out.str());
}

}  // namespace tetfsi::mesh::io
