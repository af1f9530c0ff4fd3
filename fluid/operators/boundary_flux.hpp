#pragma once
/// @file boundary_flux.hpp
/// The boundary term of the weak divergence, (D u)_i = -(G^T V u)_i + int_dOmega phi_i (u_b . n) dA,
/// on triangles with a prescribed normal velocity (moving solids, inflow patches).
///
/// With u_b linear on the triangle (P1 from its three vertex velocities u_j) the integral is exact:
///   f_i = sum_j M_ij (u_j . n),   M_ij = int phi_i phi_j dA = A (1 + delta_ij) / 12
/// (the P1 surface mass matrix). The coupling builds H from this same matrix and J = H^T, so that
/// the pressure's work on the solid equals the flux work on the fluid and eq. (7) of Chentanez et
/// al. 2006 scales into a symmetric system (as in Robinson-Mosher, Shinar, Gretarsson, Su & Fedkiw
/// 2008, "Two-way coupling of fluids to rigid and deformable solids and shells", sec. 5).
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
