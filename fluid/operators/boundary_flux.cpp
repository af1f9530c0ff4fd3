#include "fluid/operators/boundary_flux.hpp"

#include <stdexcept>

namespace tetfsi::fluid {

Eigen::VectorXd boundary_flux(const FluidMesh& mesh, const std::vector<int>& faces,
                              const std::vector<std::array<Eigen::Vector3d, 3>>& velocity) {
  if (faces.size() != velocity.size())
    throw std::invalid_argument("boundary_flux: faces and velocity lists differ in length");
  Eigen::VectorXd f = Eigen::VectorXd::Zero(mesh.num_nodes());
  for (size_t k = 0; k < faces.size(); ++k) {
    const BoundaryFace& bf = mesh.boundary_faces.at(faces[k]);
    double un[3];
    for (int j = 0; j < 3; ++j) un[j] = velocity[k][j].dot(bf.normal);
    const double s = un[0] + un[1] + un[2];
    for (int i = 0; i < 3; ++i) f[bf.nodes[i]] += bf.area / 12.0 * (s + un[i]);
  }
  return f;
}

Eigen::SparseMatrix<double> boundary_flux_matrix(const FluidMesh& mesh, const std::vector<int>& faces) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(27 * faces.size());
  for (int fi : faces) {
    const BoundaryFace& bf = mesh.boundary_faces.at(fi);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double m = bf.area / 12.0 * (i == j ? 2.0 : 1.0);
        for (int c = 0; c < 3; ++c) trip.emplace_back(bf.nodes[i], 3 * bf.nodes[j] + c, m * bf.normal[c]);
      }
  }
  Eigen::SparseMatrix<double> b(mesh.num_nodes(), 3 * mesh.num_nodes());
  b.setFromTriplets(trip.begin(), trip.end());
  return b;
}

}  // namespace tetfsi::fluid
