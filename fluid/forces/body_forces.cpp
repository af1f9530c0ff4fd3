#include "fluid/forces/body_forces.hpp"

#include <cmath>

namespace tetfsi::fluid {

void add_buoyancy(const FluidMesh& mesh, const Eigen::VectorXd& smoke, const Eigen::VectorXd& temperature,
                  const Eigen::Vector3d& gravity, const BuoyancyParams& params, double h, TetVectors& u) {
  const double g = gravity.norm();
  if (g == 0.0 || (params.alpha == 0.0 && params.beta == 0.0)) return;
  const Eigen::Vector3d up = -gravity / g;
  for (int t = 0; t < mesh.num_tets(); ++t)
    u[t] += h * (-params.alpha * smoke[t] + params.beta * (temperature[t] - params.ambient_temperature)) * up;
}

TetVectors vorticity(const FluidMesh& mesh, const TetVectors& u) {
  const TetVectors un = average_to_nodes(mesh, u);
  TetVectors w(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) c += mesh.grad[t][k].cross(un[mesh.tets[t][k]]);
    w[t] = c;
  }
  return w;
}

void add_vorticity_confinement(const FluidMesh& mesh, double epsilon, double h, TetVectors& u) {
  if (epsilon == 0.0) return;
  const TetVectors w = vorticity(mesh, u);
  Eigen::VectorXd mag(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) mag[t] = w[t].norm();
  const Eigen::VectorXd mag_nodes = average_to_nodes(mesh, mag);
  const TetVectors grad_mag = gradient(mesh, mag_nodes);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const double gn = grad_mag[t].norm();
    if (gn < 1e-300) continue;
    const Eigen::Vector3d n = grad_mag[t] / gn;
    u[t] += h * epsilon * std::cbrt(mesh.volume[t]) * n.cross(w[t]);
  }
}

}  // namespace tetfsi::fluid
