#include "mesh/io/vtu_writer.hpp"

#include <cstring>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "mesh/io/atomic_file.hpp"

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

// VTK inline binary block: base64(UInt64 byte count) + base64(payload), encoded together.
template <class T>
std::string encode(const std::vector<T>& values) {
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::vector<unsigned char> buffer(sizeof(bytes) + bytes);
  std::memcpy(buffer.data(), &bytes, sizeof(bytes));
  if (bytes) std::memcpy(buffer.data() + sizeof(bytes), values.data(), bytes);
  return base64(buffer.data(), buffer.size());
}

const char* vtk_type_name(double) { return "Float64"; }
const char* vtk_type_name(std::int64_t) { return "Int64"; }
const char* vtk_type_name(std::uint8_t) { return "UInt8"; }

template <class T>
void write_array(std::ostream& out, const std::string& name, int components,
                 const std::vector<T>& values) {
  out << "        <DataArray type=\"" << vtk_type_name(T{}) << "\" Name=\"" << name
      << "\" NumberOfComponents=\"" << components << "\" format=\"binary\">\n          "
      << encode(values) << "\n        </DataArray>\n";
}

void check_field(const DataArray& a, std::size_t count, const char* where) {
  if (a.components < 1 || a.values.size() != count * static_cast<std::size_t>(a.components)) {
    throw std::invalid_argument(std::string(where) + " field '" + a.name + "' has " +
                                std::to_string(a.values.size()) + " values, expected " +
                                std::to_string(count) + " x " + std::to_string(a.components));
  }
}

}  // namespace

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

void write_vtu(const std::filesystem::path& path, const UnstructuredGrid& grid) {
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
  write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt64\">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << grid.num_points() << "\" NumberOfCells=\""
        << grid.num_cells() << "\">\n";
    out << "      <PointData>\n";
    for (const auto& a : grid.point_data) write_array(out, a.name, a.components, a.values);
    out << "      </PointData>\n      <CellData>\n";
    for (const auto& a : grid.cell_data) write_array(out, a.name, a.components, a.values);
    out << "      </CellData>\n      <Points>\n";
    std::vector<double> xyz;
    xyz.reserve(3 * grid.points.size());
    for (const auto& p : grid.points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    write_array(out, "Points", 3, xyz);
    out << "      </Points>\n      <Cells>\n";
    write_array(out, "connectivity", 1, grid.connectivity);
    write_array(out, "offsets", 1, grid.offsets);
    write_array(out, "types", 1, grid.types);
    out << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  });
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
