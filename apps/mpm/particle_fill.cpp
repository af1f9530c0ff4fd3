#include "apps/mpm/particle_fill.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <vector>

#include "mesh/surface_checks.hpp"

namespace tetfsi::mpm_setup {

std::function<bool(const mpm::Vec3&)> inside_surface(const mesh::SurfaceMesh& s) {
  struct Cache {
    mesh::SurfaceMesh s;
    double shift_x = 0, shift_y = 0;
    std::map<std::pair<double, double>, std::vector<double>> columns;  // (x, y) -> sorted crossing z
  };
  auto c = std::make_shared<Cache>();
  c->s = s;
  Eigen::Vector3d lo, hi;
  mesh::bounding_box(s, lo, hi);
  const double size = (hi - lo).norm();
  c->shift_x = 1.2345678e-9 * size;  // irrational-looking offsets: off the lattice of the mesh
  c->shift_y = 0.8765432e-9 * size;
  return [c](const mpm::Vec3& p) {
    const double x = p[0] + c->shift_x, y = p[1] + c->shift_y;
    auto it = c->columns.find({p[0], p[1]});
    if (it == c->columns.end()) {
      std::vector<double> z;
      for (const auto& t : c->s.triangles) {
        const auto &a = c->s.vertices[t[0]], &b = c->s.vertices[t[1]], &d = c->s.vertices[t[2]];
        // Barycentric coordinates of (x, y) in the projected triangle.
        const double det = (b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]);
        if (det == 0) continue;  // vertical triangle: the ray does not cross it
        const double l1 = ((x - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (y - a[1])) / det;
        const double l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
        if (l1 < 0 || l2 < 0 || l1 + l2 > 1) continue;
        z.push_back(a[2] + l1 * (b[2] - a[2]) + l2 * (d[2] - a[2]));
      }
      std::sort(z.begin(), z.end());
      it = c->columns.emplace(std::make_pair(p[0], p[1]), std::move(z)).first;
    }
    const auto& z = it->second;
    const auto above = z.end() - std::upper_bound(z.begin(), z.end(), p[2]);
    return above % 2 == 1;
  };
}

}  // namespace tetfsi::mpm_setup
