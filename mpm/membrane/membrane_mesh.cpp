#include "mpm/membrane/membrane_mesh.hpp"

#include <stdexcept>

namespace tetfsi::mpm {

QuadMesh rectangle_mesh(const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                        int nu, int nv) {
  if (nu < 1 || nv < 1) throw std::invalid_argument("rectangle_mesh: need at least one quad per direction");
  QuadMesh m;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) m.nodes.push_back(origin + (double(i) / nu) * u + (double(j) / nv) * v);
  auto id = [&](int i, int j) { return i + (nu + 1) * j; };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) m.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

QuadMesh extruded_polyline(const std::vector<Eigen::Vector2d>& points, double z0, double z1, int nz) {
  if (points.size() < 2 || nz < 1) throw std::invalid_argument("extruded_polyline: need >= 2 points and nz >= 1");
  QuadMesh m;
  const int np = static_cast<int>(points.size());
  for (int k = 0; k <= nz; ++k)
    for (const auto& p : points) m.nodes.emplace_back(p[0], p[1], z0 + (z1 - z0) * k / nz);
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i + 1 < np; ++i)
      m.quads.push_back({i + np * k, i + 1 + np * k, i + 1 + np * (k + 1), i + np * (k + 1)});
  return m;
}

}  // namespace tetfsi::mpm
