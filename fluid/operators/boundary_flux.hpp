#pragma once
/// @file boundary_flux.hpp
/// The boundary term of the weak divergence, (D u)_i = -(G^T V u)_i + int_dOmega phi_i (u_b . n) dA,
/// on triangles with a prescribed normal velocity (moving solids, inflow patches).
///
/// With u_b linear on the triangle (P1 from its three vertex velocities u_j) the integral is exact:
///   f_i = sum_j M_ij (u_j . n),   M_ij = int phi_i phi_j dA = A (1 + delta_ij) / 12
/// (the P1 surface mass matrix). The coupling builds H from this same matrix and J = H^T
/// (shared/design.md "Coupling: decided", methods.md sec. 3).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::fluid {

/// f (N) = sum over the listed boundary faces of int phi_i (u_b . n_out) dA [m^3/s].
/// @param faces     indices into mesh.boundary_faces
/// @param velocity  per listed face, the velocities [m/s] at its 3 nodes (same order as face.nodes)
Eigen::VectorXd boundary_flux(const FluidMesh& mesh, const std::vector<int>& faces,
                              const std::vector<std::array<Eigen::Vector3d, 3>>& velocity);

/// The same map as a matrix B (N x 3N) acting on nodal velocities stacked [u_0x u_0y u_0z u_1x ...]:
/// f = B u. Only nodes of the listed faces have nonzero columns.
Eigen::SparseMatrix<double> boundary_flux_matrix(const FluidMesh& mesh, const std::vector<int>& faces);

}  // namespace tetfsi::fluid
