#include "solid/scenarios/cantilever.hpp"

#include <cmath>

#include "mesh/structured_box.hpp"

namespace tetfsi::solid {

Cantilever make_cantilever(const CantileverSpec& spec) {
  Cantilever c;
  c.spec = spec;
  c.mesh = mesh::structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d(spec.length, spec.width, spec.width),
                                spec.cells_along, spec.cells_across, spec.cells_across, mesh::solid_subdomain(0));
  c.model = std::make_unique<TetModel>(c.mesh, spec.material);
  const int n = c.mesh.num_vertices();
  const double tol = 1e-9 * spec.length;
  c.fixed_dofs.assign(3 * n, 0);
  for (int v = 0; v < n; ++v)
    if (c.mesh.vertices[v].x() < tol) {
      c.clamped_nodes.push_back(v);
      for (int a = 0; a < 3; ++a) c.fixed_dofs[3 * v + a] = 1;
    }
  // Tip face weights: each boundary triangle at x = L gives a third of its area to its nodes.
  c.tip_weights.setZero(n);
  auto at_tip = [&](int v) { return c.mesh.vertices[v].x() > spec.length - tol; };
  for (const auto& t : c.mesh.tets)
    for (int skip = 0; skip < 4; ++skip) {
      int f[3], k = 0;
      for (int i = 0; i < 4; ++i)
        if (i != skip) f[k++] = t[i];
      if (!(at_tip(f[0]) && at_tip(f[1]) && at_tip(f[2]))) continue;
      const double area = 0.5 * (c.mesh.vertices[f[1]] - c.mesh.vertices[f[0]])
                                    .cross(c.mesh.vertices[f[2]] - c.mesh.vertices[f[0]])
                                    .norm();
      for (int v : f) c.tip_weights[v] += area / 3.0;
    }
  c.tip_weights /= c.tip_weights.sum();
  return c;
}

Eigen::VectorXd Cantilever::tip_load(const Eigen::Vector3d& force) const {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * tip_weights.size());
  for (Eigen::Index v = 0; v < tip_weights.size(); ++v) f.segment<3>(3 * v) = tip_weights[v] * force;
  return f;
}

double Cantilever::tip_displacement(const Eigen::VectorXd& d, int axis) const {
  double w = 0;
  for (Eigen::Index v = 0; v < tip_weights.size(); ++v) w += tip_weights[v] * d[3 * v + axis];
  return w;
}

double Cantilever::euler_bernoulli_deflection(double P) const {
  return P * std::pow(spec.length, 3) / (3.0 * spec.material.youngs_modulus * second_moment());
}

double Cantilever::euler_bernoulli_omega1() const {
  const double A = spec.width * spec.width;
  return 1.875104 * 1.875104 *
         std::sqrt(spec.material.youngs_modulus * second_moment() / (spec.material.density * A * std::pow(spec.length, 4)));
}

CantileverSpec slender_cantilever_spec(int m) {
  CantileverSpec s;
  s.cells_across = m;
  s.cells_along = 10 * m;
  s.material.youngs_modulus = 1e6;
  s.material.poisson_ratio = 0.0;
  s.material.density = 1000;
  return s;
}

}  // namespace tetfsi::solid
