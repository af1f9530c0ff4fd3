#include "mesh/volume_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "mesh/cell_checks.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/io/msh_reader.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "support/number_text.hpp"

namespace tetfsi::mesh {
namespace {

double longest_edge(const TetMesh& m, int t) {
  double l = 0;
  const auto& v = m.tets[t];
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) l = std::max(l, (m.vertices[v[a]] - m.vertices[v[b]]).norm());
  return l;
}

}  // namespace

std::string volume_mesh_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw MeshError(path + ": not found or not a regular file");
  if (std::filesystem::file_size(path, ec) > kMaxSurfaceBytes)
    throw MeshError(path + ": larger than " + std::to_string(kMaxSurfaceBytes >> 20) + " MiB");
  if (ext != ".msh" && ext != ".vtu")
    throw MeshError(path + ": unknown volume mesh extension '" + ext + "' (expected .vtu or .msh)");
  return ext;
}

std::vector<std::vector<int>> read_vtu_cells(const std::string& path, bool hexes, std::vector<Eigen::Vector3d>& points) {
  const auto want = static_cast<std::uint8_t>(hexes ? io::VtkCell::Hexahedron : io::VtkCell::Tetra);
  const auto other = static_cast<std::uint8_t>(hexes ? io::VtkCell::Tetra : io::VtkCell::Hexahedron);
  const std::int64_t n = hexes ? 8 : 4;
  return as_mesh_error([&] {
    const io::UnstructuredGrid grid = io::read_vtu(path);
    points = grid.points;
    std::vector<std::vector<int>> cells;
    std::int64_t begin = 0;
    for (int c = 0; c < grid.num_cells(); ++c) {
      const std::int64_t end = grid.offsets[c];
      if (grid.types[c] != want || end - begin != n)
        throw MeshError(path + ": cell " + std::to_string(c) + " has VTK type " + std::to_string(grid.types[c]) +
                        " with " + std::to_string(end - begin) + " points; only " +
                        (hexes ? "hexahedra (VTK_HEXAHEDRON, type 12, 8 points)" : "tetrahedra (VTK_TETRA, type 10, 4 points)") +
                        " are supported here" +
                        (grid.types[c] != other ? ""
                         : hexes ? " (a tetrahedral mesh is for model \"tet_fem\")"
                                 : " (a hexahedral mesh is for model \"hex8\")"));
      cells.emplace_back(grid.connectivity.begin() + begin, grid.connectivity.begin() + end);
      begin = end;
    }
    return cells;
  });
}

TetMesh read_volume_mesh(const std::string& path) {
  if (volume_mesh_extension(path) == ".msh") return as_mesh_error([&] { return io::read_msh_tets(path); });
  TetMesh m;
  for (const auto& c : read_vtu_cells(path, false, m.vertices)) m.tets.push_back({c[0], c[1], c[2], c[3]});
  return m;
}

void check_volume_mesh(TetMesh& m, const std::string& label, std::vector<std::string>& warnings) {
  cells::check_cells_and_nodes(m.vertices, m.tets, label, "tet", "tetrahedra");
  std::vector<bool> negative(m.tets.size());
  for (int t = 0; t < m.num_tets(); ++t) {  // orientation and degeneracy
    const double vol = signed_volume(m, t), l = longest_edge(m, t);
    if (!(std::fabs(vol) > kDegenerateTet * l * l * l))
      throw MeshError(label + ": tet " + std::to_string(t) + " is degenerate (volume " + number_text(vol) +
                      " m^3 for a longest edge of " + number_text(l) + " m)");
    negative[t] = vol < 0;
  }
  if (cells::all_negative(negative, label, "tet", "a tangled mesh")) {
    for (auto& t : m.tets) std::swap(t[1], t[2]);
    warnings.push_back(label + ": every tet was negatively oriented; reordered to positive orientation");
  }
  cells::check_faces_and_pieces(m.tets, kTetFaceVertices, label, "tet");
  if (const int dropped = cells::drop_unused_nodes(m.vertices, m.tets))
    warnings.push_back(label + ": " + std::to_string(dropped) + " node(s) used by no tet were dropped");
  m.subdomain.clear();
}

TetMesh import_volume_mesh(const std::string& path, const Placement& placement, std::vector<std::string>& warnings) {
  TetMesh m = read_volume_mesh(path);
  apply_placement(m.vertices, placement);
  check_volume_mesh(m, path, warnings);
  return m;
}

}  // namespace tetfsi::mesh
