#pragma once
/// @file volume_mesh_files.hpp
/// Test helpers writing tet meshes in the .vtu layouts the library's writer does not produce
/// (ASCII, raw appended), and with arbitrary cell types, for the volume-mesh reader tests.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::test {

/// ASCII .vtu of the points and cells (`cells[c]` point indices, `types[c]` VTK type).
inline void write_vtu_ascii(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
                            const std::vector<std::vector<int>>& cells, const std::vector<int>& types) {
  std::ofstream f(path);
  f.precision(17);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
    << "<UnstructuredGrid><Piece NumberOfPoints=\"" << points.size() << "\" NumberOfCells=\"" << cells.size() << "\">\n"
    << "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : points) f << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  f << "</DataArray></Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& c : cells) {
    for (int v : c) f << v << ' ';
    f << '\n';
  }
  f << "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t end = 0;
  for (const auto& c : cells) f << (end += c.size()) << ' ';
  f << "\n</DataArray><DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (int t : types) f << t << ' ';
  f << "\n</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>\n";
}

/// ASCII .vtu of a tet mesh.
inline void write_vtu_ascii(const std::filesystem::path& path, const mesh::TetMesh& m) {
  std::vector<std::vector<int>> cells;
  for (const auto& t : m.tets) cells.push_back({t[0], t[1], t[2], t[3]});
  write_vtu_ascii(path, m.vertices, cells, std::vector<int>(m.tets.size(), 10));
}

/// .vtu with raw appended data (as VTK's vtkXMLUnstructuredGridWriter writes by default, without
/// compression): UInt32 headers, Float64 points, Int32 connectivity and offsets, UInt8 types.
inline void write_vtu_appended(const std::filesystem::path& path, const mesh::TetMesh& m) {
  std::string data;
  std::vector<std::size_t> offsets;
  auto block = [&](const void* bytes, std::size_t n) {
    offsets.push_back(data.size());
    const std::uint32_t header = static_cast<std::uint32_t>(n);
    data.append(reinterpret_cast<const char*>(&header), 4);
    data.append(static_cast<const char*>(bytes), n);
  };
  std::vector<double> xyz;
  for (const auto& p : m.vertices) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  std::vector<std::int32_t> conn, offs;
  for (const auto& t : m.tets) {
    conn.insert(conn.end(), t.begin(), t.end());
    offs.push_back(static_cast<std::int32_t>(conn.size()));
  }
  const std::vector<std::uint8_t> types(m.tets.size(), 10);
  block(xyz.data(), xyz.size() * sizeof(double));
  block(conn.data(), conn.size() * 4);
  block(offs.data(), offs.size() * 4);
  block(types.data(), types.size());
  std::ofstream f(path, std::ios::binary);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt32\">\n<UnstructuredGrid><Piece NumberOfPoints=\"" << m.vertices.size()
    << "\" NumberOfCells=\"" << m.tets.size() << "\">\n"
    << "<Points><DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\""
    << offsets[0] << "\"/></Points>\n<Cells>\n"
    << "<DataArray type=\"Int32\" Name=\"connectivity\" format=\"appended\" offset=\"" << offsets[1] << "\"/>\n"
    << "<DataArray type=\"Int32\" Name=\"offsets\" format=\"appended\" offset=\"" << offsets[2] << "\"/>\n"
    << "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" << offsets[3] << "\"/>\n"
    << "</Cells></Piece></UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  f.write(data.data(), static_cast<std::streamsize>(data.size()));
  f << "\n</AppendedData>\n</VTKFile>\n";
}

}  // namespace tetfsi::test
