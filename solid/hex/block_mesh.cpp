#include "solid/hex/block_mesh.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

namespace tetfsi::solid::hex {

mesh::HexMesh block_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz) {
  if (nx < 1 || ny < 1 || nz < 1) {
    throw std::invalid_argument("block_mesh: cell counts must be >= 1, got " + std::to_string(nx) + " x " +
                                std::to_string(ny) + " x " + std::to_string(nz));
  }
  if (!((hi - lo).minCoeff() > 0.0)) throw std::invalid_argument("block_mesh: need hi > lo in x, y and z");
  mesh::HexMesh m;
  const Eigen::Vector3d h = (hi - lo).cwiseQuotient(Eigen::Vector3d(nx, ny, nz));
  m.vertices.reserve(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) m.vertices.push_back(lo + Eigen::Vector3d(i * h.x(), j * h.y(), k * h.z()));
    }
  }
  auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  m.hexes.reserve(static_cast<std::size_t>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
      }
    }
  }
  return m;
}

namespace {
bool inside(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double tol) {
  return (p.array() >= lo.array() - tol).all() && (p.array() <= hi.array() + tol).all();
}
}  // namespace

std::vector<int> nodes_in_box(const mesh::HexMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                              double tol) {
  std::vector<int> nodes;
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    if (inside(mesh.vertices[i], lo, hi, tol)) nodes.push_back(i);
  }
  return nodes;
}

std::vector<std::array<int, 4>> boundary_faces_in_box(const mesh::HexMesh& mesh, const Eigen::Vector3d& lo,
                                                      const Eigen::Vector3d& hi, double tol) {
  // Count each face by its sorted node set; faces seen once are on the boundary.
  std::map<std::array<int, 4>, std::pair<int, std::array<int, 4>>> faces;
  for (const auto& h : mesh.hexes) {
    for (const auto& f : kHexFaces) {
      const std::array<int, 4> q{h[f[0]], h[f[1]], h[f[2]], h[f[3]]};
      auto key = q;
      std::sort(key.begin(), key.end());
      auto [it, added] = faces.emplace(key, std::make_pair(1, q));
      if (!added) ++it->second.first;
    }
  }
  std::vector<std::array<int, 4>> out;
  for (const auto& [key, value] : faces) {
    if (value.first != 1) continue;
    const auto& q = value.second;
    if (std::all_of(q.begin(), q.end(), [&](int v) { return inside(mesh.vertices[v], lo, hi, tol); })) {
      out.push_back(q);
    }
  }
  return out;
}

}  // namespace tetfsi::solid::hex
