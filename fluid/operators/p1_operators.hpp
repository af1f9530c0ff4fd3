#pragma once
/// @file p1_operators.hpp
/// Gradient, weak divergence and Laplacian of the nodal-pressure / tet-velocity scheme
/// (Ando, Thuerey, Wojtan 2013, sec. 3; the projection [grad]^T V [grad] p = [grad]^T V u).
///
/// With G the (3T x N) gradient of the P1 interpolant, (G p)_t = sum_k p_{t_k} grad(phi_k)|_t, and
/// V = diag(V_t) (each repeated 3 times):
///  - Laplacian (P1 stiffness):  L = G^T V G,   L_ij = sum_t V_t grad(phi_i).grad(phi_j)   [m]
///  - weak divergence:           (D u)_i = int phi_i div u = -(G^T V u)_i + int_dOmega phi_i u.n
///    so D = -G^T V up to the boundary flux term: the divergence is the negative V-weighted adjoint
///    of the gradient, and the projection u = u* - (h/rho) G p is V-orthogonal (energy conserving).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <tbb/parallel_for.h>

#include <type_traits>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::fluid {

using TetVectors = std::vector<Eigen::Vector3d>;  ///< one vector per fluid tet

/// Per-tet gradient of the nodal field p: (G p)_t = sum_k p_{t_k} grad(phi_k)|_t [unit(p)/m].
TetVectors gradient(const FluidMesh& mesh, const Eigen::VectorXd& p);

/// (G^T V u)_i = sum_{t ni i} V_t grad(phi_i)|_t . u_t  [m^3/s for u in m/s]. The weak divergence
/// is -(G^T V u) + boundary flux (boundary_flux.hpp).
Eigen::VectorXd gradient_transpose_volume(const FluidMesh& mesh, const TetVectors& u);


/// P1 stiffness matrix L = G^T V G (N x N), symmetric positive semi-definite (constant null space):
/// L_ij = sum_{t ni i,j} V_t grad(phi_i)|_t . grad(phi_j)|_t (Ando, Thuerey & Wojtan 2013, sec. 3).
Eigen::SparseMatrix<double> assemble_laplacian(const FluidMesh& mesh);

/// scale * L restricted to the rows and columns of the unknowns: entry (unknown[i], unknown[j]) of
/// the m x m result is scale * L_ij for the nodes i, j with unknown[] >= 0 (a node with -1 is left
/// out).
///
/// Gathered column by column in parallel over each node's tets in ascending order (the order of a
/// triplet sum in tet order), then scaled: deterministic, and bit for bit L's entries filtered and
/// scaled afterwards. `earlier` (optional): a matrix this returned before, taken over (its pattern
/// reused, values overwritten) when the entries fall on the same places, as on a moved mesh with
/// the same unknowns (mesh/column_gather.hpp): one pass instead of two and no sort.
Eigen::SparseMatrix<double> assemble_laplacian(const FluidMesh& mesh, const std::vector<int>& unknown, int m,
                                              double scale = 1.0, Eigen::SparseMatrix<double>* earlier = nullptr);

/// Weighted average of per-tet values at the nodes, x_i = sum_{t ni i} w_t x_t / sum_{t ni i} w_t,
/// with w_t = `weight`[t] (nullptr: the tet volumes V_t). Summed over each node's tets in
/// ascending order, nodes in parallel: deterministic. Value: double or a fixed-size Eigen vector.
/// The values are read as value_of(t) (no array of them needed).
template <class Value, class ValueOf>
std::vector<Value> weighted_node_average_of(const FluidMesh& mesh, const ValueOf& value_of,
                                            const std::vector<double>* weight = nullptr) {
  const std::vector<double>& w = weight ? *weight : mesh.volume;
  std::vector<Value> out(mesh.num_nodes());
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    Value sum;
    if constexpr (std::is_arithmetic_v<Value>) sum = 0.0;
    else sum = Value::Zero();
    double total = 0.0;
    for (int t : mesh.node_tets[i]) {
      sum += w[t] * value_of(t);
      total += w[t];
    }
    out[i] = sum / total;
  });
  return out;
}

/// weighted_node_average_of for the values[t].
template <class Value>
std::vector<Value> weighted_node_average(const FluidMesh& mesh, const std::vector<Value>& values,
                                         const std::vector<double>* weight = nullptr) {
  return weighted_node_average_of<Value>(mesh, [&](int t) -> const Value& { return values[t]; }, weight);
}

/// Volume-weighted average of tet vectors at the nodes: u_i = sum_t V_t u_t / sum_t V_t
/// (the velocity reconstruction used for advection and output; it smooths, see advection docs).
TetVectors average_to_nodes(const FluidMesh& mesh, const TetVectors& u);

/// Volume-weighted average of a per-tet scalar at the nodes.
Eigen::VectorXd average_to_nodes(const FluidMesh& mesh, const Eigen::VectorXd& s);

/// Kinetic energy per unit density: 1/2 sum_t V_t |u_t|^2 [m^5/s^2].
double kinetic_energy(const FluidMesh& mesh, const TetVectors& u);

}  // namespace tetfsi::fluid
