#include "fluid/mpm/grid.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tetfsi::mpm {

Grid Grid::covering(const Vec3& lo, const Vec3& hi, double dx) {
  if (!(dx > 0.0)) throw std::invalid_argument("mpm::Grid: cell size must be positive");
  Grid g;
  g.lo = lo;
  g.dx = dx;
  for (int a = 0; a < 3; ++a) {
    if (!(hi[a] > lo[a])) throw std::invalid_argument("mpm::Grid: empty box on axis " + std::to_string(a));
    g.cells[a] = std::max(1, static_cast<int>(std::ceil((hi[a] - lo[a]) / dx - 1e-9)));
  }
  return g;
}

Vec3 Grid::node_position(std::int64_t id) const {
  const std::int64_t nx = cells[0] + 1, ny = cells[1] + 1;
  const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
  return lo + dx * Vec3(double(i), double(j), double(k));
}

Stencil Grid::stencil(const Vec3& x) const {
  if (!contains(x)) {
    std::ostringstream msg;
    msg << "mpm::Grid: point (" << x.transpose() << ") is outside the background grid";
    throw std::out_of_range(msg.str());
  }
  return stencil_unchecked(x);
}

std::vector<std::array<bool, 3>> Grid::build_constraint_mask() const {
  std::vector<std::array<bool, 3>> mask(static_cast<size_t>(num_nodes()), {false, false, false});
  for (int k = 0; k <= cells[2]; ++k)
    for (int j = 0; j <= cells[1]; ++j)
      for (int i = 0; i <= cells[0]; ++i) {
        auto& m = mask[static_cast<size_t>(node_index(i, j, k))];
        const int idx[3] = {i, j, k};
        for (int a = 0; a < 3; ++a) {
          if (constrained_axes[a]) m[a] = true;
          for (int side = 0; side < 2; ++side) {
            const bool on_face = side == 0 ? idx[a] == 0 : idx[a] == cells[a];
            const FaceBc bc = faces[2 * a + side];
            if (!on_face || bc == FaceBc::Free) continue;
            if (bc == FaceBc::Slip) m[a] = true;
            if (bc == FaceBc::Fixed) m = {true, true, true};
          }
        }
      }
  return mask;
}

}  // namespace tetfsi::mpm
