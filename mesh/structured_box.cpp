#include "mesh/structured_box.hpp"

#include <stdexcept>

namespace tetfsi::mesh {

TetMesh structured_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz,
                       int subdomain) {
  if (nx < 1 || ny < 1 || nz < 1) throw std::invalid_argument("structured_box: cell counts must be >= 1");
  if (!((hi - lo).array() > 0.0).all()) throw std::invalid_argument("structured_box: hi must exceed lo");
  TetMesh m;
  const Eigen::Vector3d h = (hi - lo).cwiseQuotient(Eigen::Vector3d(nx, ny, nz));
  auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  m.vertices.reserve(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.vertices.emplace_back(lo + h.cwiseProduct(Eigen::Vector3d(i, j, k)));

  // The 6 monotone paths from corner (0,0,0) to (1,1,1): each path visits 4 corners of the cell
  // and the 4 corners span one tet. The axis orders below are the 6 permutations of (x, y, z).
  static const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  m.tets.reserve(6 * static_cast<std::size_t>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& order : orders) {
          int c[3] = {i, j, k};
          std::array<int, 4> t{};
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[order[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          if (signed_volume(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], m.vertices[t[3]]) < 0)
            std::swap(t[2], t[3]);
          m.tets.push_back(t);
        }
  m.subdomain.assign(m.tets.size(), subdomain);
  return m;
}

}  // namespace tetfsi::mesh
