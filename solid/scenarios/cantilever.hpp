#pragma once
/// @file cantilever.hpp
/// The cantilever set-up shared by the validation tests, the benchmark and the scenes: a beam
/// [0, L] x [0, b] x [0, b] of structured tets (mesh/structured_box.hpp), clamped at x = 0,
/// loaded at the free end x = L. Reference: Euler-Bernoulli (benchmarks.md sec. 3.4):
/// tip deflection P L^3 / (3 E I), first frequency (1.875104)^2 sqrt(E I / (rho A L^4)),
/// I = b^4 / 12, A = b^2.
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <vector>

#include "mesh/tet_mesh.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::solid {

struct CantileverSpec {
  double length = 1.0;     ///< L [m]
  double width = 0.1;      ///< b, square section [m]
  int cells_along = 20;    ///< cells along x; cells_across along y and z
  int cells_across = 2;
  TetMaterial material;
};

struct Cantilever {
  CantileverSpec spec;
  mesh::TetMesh mesh;
  std::unique_ptr<TetModel> model;
  std::vector<int> clamped_nodes;   ///< nodes at x = 0
  std::vector<char> fixed_dofs;     ///< their 3 DOFs
  Eigen::VectorXd tip_weights;      ///< per node: share of the tip face area (sum 1), zero elsewhere

  /// Nodal force vector of a total tip force `force` [N] spread by tip_weights.
  Eigen::VectorXd tip_load(const Eigen::Vector3d& force) const;
  /// Area-weighted mean displacement of the tip face in direction `axis`.
  double tip_displacement(const Eigen::VectorXd& d, int axis) const;

  double second_moment() const { return std::pow(spec.width, 4) / 12.0; }
  /// Euler-Bernoulli tip deflection for tip load P [N] (magnitude) [m].
  double euler_bernoulli_deflection(double P) const;
  /// Euler-Bernoulli first bending angular frequency [rad/s].
  double euler_bernoulli_omega1() const;
};

/// @throws SolidError / std::invalid_argument on bad sizes or material
Cantilever make_cantilever(const CantileverSpec& spec);

/// The validation beam of the tests and benchmark: m x m cells across, 10 m along (L/b = 10),
/// E = 1e6 Pa, nu = 0 (no Poisson stiffening, so Euler-Bernoulli applies), rho = 1000 kg/m^3.
CantileverSpec slender_cantilever_spec(int m);

}  // namespace tetfsi::solid
