#include "solid/hex/hex_output.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tetfsi::solid::hex {

mesh::io::UnstructuredGrid make_hex_grid(const HexModel& model, const Eigen::VectorXd& u) {
  if (u.size() != 3 * model.num_nodes() || !u.allFinite()) {
    throw std::runtime_error("hex output: displacement is non-finite or of the wrong size; not writing it");
  }
  auto grid = mesh::io::make_grid(model.mesh());
  grid.add_point_data("displacement", 3, std::vector<double>(u.data(), u.data() + u.size()));
  std::vector<double> cauchy, pk2;
  model.element_stresses(u, cauchy, pk2);
  std::vector<double> mises(model.mesh().num_hexes());
  for (std::size_t e = 0; e < mises.size(); ++e) {
    const double* s = &cauchy[6 * e];
    if (!std::isfinite(s[0])) {
      throw std::runtime_error("hex output: element " + std::to_string(e) + " is inverted; not writing it");
    }
    mises[e] = std::sqrt(0.5 * ((s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) +
                                (s[2] - s[0]) * (s[2] - s[0])) +
                         3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
  }
  grid.add_cell_data("cauchy_stress", 6, std::move(cauchy));
  grid.add_cell_data("pk2_stress", 6, std::move(pk2));
  grid.add_cell_data("von_mises", 1, std::move(mises));
  return grid;
}

void write_hex_vtu(const std::filesystem::path& path, const HexModel& model, const Eigen::VectorXd& u) {
  mesh::io::write_vtu(path, make_hex_grid(model, u));
}

}  // namespace tetfsi::solid::hex
