#pragma once
/// @file node_fit.hpp
/// Polynomial fits of the tet velocities around each node, for the viscous step's nodal field and
/// the tets' smooth reference (implicit_viscosity.hpp).
///
/// At node i, the weighted least-squares fit of a quadratic q_i(x) = a + B d + (1/2) d^T C d,
/// d = x - x_i, to the tet velocities at their centroids,
///   min sum_t w_t |q_i(c_t) - u_t|^2  over the tets around i,
/// exact for any quadratic field on any mesh (the weighted average sum_t w_t u_t / sum_t w_t is not
/// even exact for linear fields on unstructured meshes: sum_t w_t c_t / sum_t w_t is not x_i).
/// The quadratic is fitted over the tets around i and its neighbours (those around i alone have
/// their centroids at about one distance from x_i and do not determine it); where even these do
/// not (boundary corners), a linear fit over the tets around i, then around its neighbours, and
/// last the weighted average.
#include <Eigen/Core>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"

namespace tetfsi::fluid {

/// One fit per node: q_i(x) = sum_m coefficient.col(m) * monomial_m((x - x_i) / scale).
struct NodeFits {
  std::vector<Eigen::Matrix<double, 3, 10>> coefficient;  ///< per node; unused monomials are 0
  std::vector<double> scale;                              ///< per node: largest |c_t - x_i| over the tets around it and its neighbours [m]
  /// q_i(x_i) [m/s].
  Eigen::Vector3d at_node(int i) const { return coefficient[i].col(0); }
  /// q_i(x) [m/s].
  Eigen::Vector3d at(const FluidMesh& mesh, int i, const Eigen::Vector3d& x) const;
};

/// Per node, the tets around it and its neighbours (the quadratic fit's ring), in the order of
/// discovery: a function of the mesh's topology only, so a caller may keep it while the mesh moves
/// without remeshing (FluidSolver does). Nodes in parallel: deterministic.
using NodeRings = std::vector<std::vector<int>>;
NodeRings node_rings(const FluidMesh& mesh);

/// The fits of `u` around every node, weights w_t = `weight` (0: the tet is left out), over
/// `rings` (node_rings(mesh)). Nodes in parallel: deterministic.
NodeFits fit_at_nodes(const FluidMesh& mesh, const std::vector<double>& weight, const TetVectors& u,
                      const NodeRings& rings);

}  // namespace tetfsi::fluid
