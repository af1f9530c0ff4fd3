#pragma once
/// @file hex8_element.hpp
/// The geometrically nonlinear 8-node hexahedron in the Total Lagrangian form: per element a 24 x 24 tangent K_T = K_L + K_NL and internal force F_int.
///
/// Notation (Bathe 1996, Finite Element Procedures, sec. 6.3.2 for the TL form):
///  - N_a(xi, eta, zeta) = (1 + xi_a xi)(1 + eta_a eta)(1 + zeta_a zeta) / 8, trilinear, with
///    (xi_a, eta_a, zeta_a) the corners of [-1, 1]^3 in VTK_HEXAHEDRON order;
///  - J = dX/dxi, dN/dX = dN/dxi J^-1, dV = det J w_g (2 x 2 x 2 Gauss, w_g = 1, points +-1/sqrt 3);
///  - displacement gradient H_ij = du_i/dX_j = sum_a u_ai dN_a/dX_j, F = I + H;
///  - Green-Lagrange strain E = (H + H^T + H^T H) / 2, Voigt [xx yy zz 2xy 2yz 2zx];
///  - B_L = B_L0 + B_L1(u): dE_voigt = B_L du. Column (a, k) of B_L (node a, direction k):
///      row xx: F_k0 N_a,X   row yy: F_k1 N_a,Y   row zz: F_k2 N_a,Z
///      row xy: F_k0 N_a,Y + F_k1 N_a,X   row yz: F_k1 N_a,Z + F_k2 N_a,Y
///      row zx: F_k2 N_a,X + F_k0 N_a,Z
///    For u = 0 (F = I) this is the seed's B_L; the H-terms are the initial-displacement matrix B_L1;
///  - B_NL (9 x 24): rows (du_x/dX, du_x/dY, du_x/dZ, du_y/dX, ..., du_z/dZ), the seed's matrix;
///  - S_hat (9 x 9): blockdiag(S, S, S), S the 2nd Piola-Kirchhoff stress (the seed's tau_ij);
///  - K_L = int B_L^T D B_L dV,  K_NL = int B_NL^T S_hat B_NL dV,  F_int = int B_L^T S_voigt dV.
/// K_T = K_L + K_NL is the exact derivative dF_int/du (tested against finite differences).
#include <Eigen/Core>
#include <array>

#include "solid/hex/material.hpp"

namespace tetfsi::solid::hex {

using Vector24d = Eigen::Matrix<double, 24, 1>;
using Matrix24d = Eigen::Matrix<double, 24, 24>;
using Matrix83d = Eigen::Matrix<double, 8, 3>;

/// Natural coordinates of the 8 nodes in VTK_HEXAHEDRON order.
inline constexpr double kHexCorners[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

/// Shape function values N_a at natural point xi.
Eigen::Matrix<double, 8, 1> hex8_shape(const Eigen::Vector3d& xi);
/// dN_a/dxi_j at natural point xi (8 x 3).
Matrix83d hex8_shape_gradient(const Eigen::Vector3d& xi);
/// The 8 Gauss points of the 2 x 2 x 2 rule (weights all 1).
const std::array<Eigen::Vector3d, 8>& hex8_gauss_points();

/// Which hex8 a solid uses: `Enhanced` adds 9 condensed incompatible modes (hex8_enhanced.hpp),
/// which remove the shear locking of the fully integrated `Standard` element in bending.
enum class Hex8Formulation { Standard, Enhanced };

/// Why an element evaluation failed.
enum class ElementStatus { Ok, DegenerateReference, Inverted };

/// Internal force, tangent and strain energy of one element.
/// @param X       reference node positions, row a = node a [m]
/// @param u       node displacements, row a = node a [m]
/// @param f       out (optional): F_int [N], ordered [x0 y0 z0 x1 ...]
/// @param K       out (optional): K_T = K_L + K_NL [N/m]
/// @param energy  out (optional): int psi dV [J]
/// @return DegenerateReference if det J <= 0 at a Gauss point, Inverted if det F <= 0 there
ElementStatus hex8_evaluate(const Material& m, const Matrix83d& X, const Matrix83d& u, Vector24d* f,
                            Matrix24d* K, double* energy);

/// Deformation gradient F and 2nd Piola-Kirchhoff stress S averaged over the 8 Gauss points
/// (volume-weighted), for output. Returns false if the element is degenerate or inverted.
bool hex8_average_stress(const Material& m, const Matrix83d& X, const Matrix83d& u, Eigen::Matrix3d& F,
                         Eigen::Matrix3d& S);

}  // namespace tetfsi::solid::hex
