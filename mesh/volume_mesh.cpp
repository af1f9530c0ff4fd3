#include "mesh/volume_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <stdexcept>

#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/io/msh_reader.hpp"
#include "mesh/io/vtu_reader.hpp"

namespace tetfsi::mesh {
namespace {

double longest_edge(const TetMesh& m, int t) {
  double l = 0;
  const auto& v = m.tets[t];
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) l = std::max(l, (m.vertices[v[a]] - m.vertices[v[b]]).norm());
  return l;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

TetMesh read_volume_mesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw MeshError(path + ": not found or not a regular file");
  if (std::filesystem::file_size(path, ec) > kMaxSurfaceBytes)
    throw MeshError(path + ": larger than " + std::to_string(kMaxSurfaceBytes >> 20) + " MiB");
  try {
    if (ext == ".msh") return io::read_msh_tets(path);
    if (ext != ".vtu")
      throw MeshError(path + ": unknown volume mesh extension '" + ext + "' (expected .vtu or .msh)");
    const io::UnstructuredGrid grid = io::read_vtu(path);
    TetMesh m;
    m.vertices = grid.points;
    std::int64_t begin = 0;
    for (int c = 0; c < grid.num_cells(); ++c) {
      const std::int64_t end = grid.offsets[c];
      if (grid.types[c] != static_cast<std::uint8_t>(io::VtkCell::Tetra) || end - begin != 4)
        throw MeshError(path + ": cell " + std::to_string(c) + " has VTK type " + std::to_string(grid.types[c]) +
                        " with " + std::to_string(end - begin) + " points; only tetrahedra (VTK_TETRA, type 10, 4 "
                        "points) are supported");
      m.tets.push_back({static_cast<int>(grid.connectivity[begin]), static_cast<int>(grid.connectivity[begin + 1]),
                        static_cast<int>(grid.connectivity[begin + 2]), static_cast<int>(grid.connectivity[begin + 3])});
      begin = end;
    }
    return m;
  } catch (const MeshError&) {
    throw;
  } catch (const std::exception& e) {  // the readers' std::runtime_error already names the file
    throw MeshError(e.what());
  }
}

void check_volume_mesh(TetMesh& m, const std::string& label, std::vector<std::string>& warnings) {
  if (m.tets.empty()) throw MeshError(label + ": the mesh has no tetrahedra");
  for (int i = 0; i < m.num_vertices(); ++i)
    if (!m.vertices[i].allFinite()) throw MeshError(label + ": node " + std::to_string(i) + " has a non-finite coordinate");
  // Orientation and degeneracy.
  int negative = 0, first_negative = -1, first_positive = -1;
  for (int t = 0; t < m.num_tets(); ++t) {
    auto v = m.tets[t];
    for (int a : v)
      if (a < 0 || a >= m.num_vertices()) throw MeshError(label + ": tet " + std::to_string(t) + " refers to a missing node");
    std::sort(v.begin(), v.end());
    if (std::adjacent_find(v.begin(), v.end()) != v.end())
      throw MeshError(label + ": tet " + std::to_string(t) + " repeats a node (degenerate)");
    const double vol = signed_volume(m, t), l = longest_edge(m, t);
    if (!(std::fabs(vol) > kDegenerateTet * l * l * l))
      throw MeshError(label + ": tet " + std::to_string(t) + " is degenerate (volume " + std::to_string(vol) +
                      " m^3 for a longest edge of " + std::to_string(l) + " m)");
    if (vol < 0) ++negative, first_negative = first_negative < 0 ? t : first_negative;
    else if (first_positive < 0) first_positive = t;
  }
  if (negative > 0 && negative < m.num_tets()) {
    const bool few = negative <= m.num_tets() - negative;
    const int t = few ? first_negative : first_positive;
    throw MeshError(label + ": tet " + std::to_string(t) + " is inverted: " + std::to_string(few ? negative : m.num_tets() - negative) +
                    " of " + std::to_string(m.num_tets()) + " tets have the opposite orientation of the others (a tangled mesh)");
  }
  if (negative == m.num_tets()) {
    for (auto& t : m.tets) std::swap(t[1], t[2]);
    warnings.push_back(label + ": every tet was negatively oriented; reordered to positive orientation");
  }
  // Faces: at most two tets each; face neighbours joined into pieces.
  std::map<std::array<int, 3>, std::pair<int, int>> faces;  // sorted face -> (count, first tet)
  std::vector<int> parent(m.num_tets());
  std::iota(parent.begin(), parent.end(), 0);
  for (int t = 0; t < m.num_tets(); ++t)
    for (const auto& f : kTetFaceVertices) {
      std::array<int, 3> key{m.tets[t][f[0]], m.tets[t][f[1]], m.tets[t][f[2]]};
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces.try_emplace(key, 0, t);
      if (++it->second.first > 2)
        throw MeshError(label + ": the face (" + std::to_string(key[0]) + ", " + std::to_string(key[1]) + ", " +
                        std::to_string(key[2]) + ") of tet " + std::to_string(t) + " is shared by more than two tets "
                        "(overlapping or duplicate tets)");
      if (!inserted) parent[find_root(parent, t)] = find_root(parent, it->second.second);
    }
  int pieces = 0;
  for (int t = 0; t < m.num_tets(); ++t) pieces += find_root(parent, t) == t;
  if (pieces > 1)
    throw MeshError(label + ": the tets form " + std::to_string(pieces) + " separate pieces (not connected through "
                    "shared faces); give each piece as its own solid");
  // Unused nodes.
  std::vector<int> map(m.vertices.size(), -1);
  int used = 0;
  for (const auto& t : m.tets)
    for (int a : t) map[a] = 0;
  std::vector<Eigen::Vector3d> kept;
  for (std::size_t i = 0; i < map.size(); ++i)
    if (map[i] == 0) map[i] = used++, kept.push_back(m.vertices[i]);
  if (used < m.num_vertices()) {
    warnings.push_back(label + ": " + std::to_string(m.num_vertices() - used) + " node(s) used by no tet were dropped");
    for (auto& t : m.tets)
      for (int& a : t) a = map[a];
    m.vertices = std::move(kept);
  }
  m.subdomain.clear();
}

TetMesh import_volume_mesh(const std::string& path, const Placement& placement, std::vector<std::string>& warnings) {
  TetMesh m = read_volume_mesh(path);
  apply_placement(m.vertices, placement);
  check_volume_mesh(m, path, warnings);
  return m;
}

}  // namespace tetfsi::mesh
