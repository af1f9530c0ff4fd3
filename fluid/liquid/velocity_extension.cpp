#include "fluid/liquid/velocity_extension.hpp"

#include <stdexcept>

namespace tetfsi::fluid {

void extend_velocity(const FluidMesh& mesh, const std::vector<char>& keep, int layers, TetVectors& u) {
  const int nt = mesh.num_tets();
  if (static_cast<int>(keep.size()) != nt || static_cast<int>(u.size()) != nt)
    throw std::invalid_argument("extend_velocity: sizes do not match the mesh");
  std::vector<char> known = keep;
  std::vector<int> front;
  for (int t = 0; t < nt; ++t)
    if (!known[t]) front.push_back(t);
  for (int layer = 0; layer < layers && !front.empty(); ++layer) {
    std::vector<int> filled, rest;
    std::vector<Eigen::Vector3d> value;
    for (int t : front) {
      Eigen::Vector3d s = Eigen::Vector3d::Zero();
      int n = 0;
      for (int nb : mesh.neighbor[t])
        if (nb >= 0 && known[nb]) {
          s += u[nb];
          ++n;
        }
      if (n > 0) {
        filled.push_back(t);
        value.push_back(s / n);
      } else {
        rest.push_back(t);
      }
    }
    if (filled.empty()) break;
    for (size_t k = 0; k < filled.size(); ++k) {
      u[filled[k]] = value[k];
      known[filled[k]] = 1;
    }
    front = std::move(rest);
  }
  for (int t : front) u[t].setZero();
}

}  // namespace tetfsi::fluid
