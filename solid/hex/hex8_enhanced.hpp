#pragma once
/// @file hex8_enhanced.hpp
/// The Total Lagrangian hex8 with 9 enhanced (incompatible-mode) parameters on the displacement
/// gradient, condensed at element level: Wilson's incompatible modes (Wilson, Taylor, Doherty &
/// Ghaboussi 1973) with Taylor's correction (Taylor, Beresford & Wilson 1976) that makes every
/// distorted mesh pass the patch test, used at finite strain in the form of Simo & Armero 1992
/// (the enhanced field added to the displacement gradient, 9 parameters in 3D); the same idea as
/// CalculiX's C3D8I, whose numbers differ (solid/hex/README.md, Cook's membrane).
///
///   F = I + sum_a u_a (x) grad N_a + sum_m alpha_m (x) G_m,          m = 1..3,
///   G_m(xi) = (j0 / j(xi)) J0^-T dM_m/dxi,   M_m = 1 - xi_m^2,
/// J0 = dX/dxi and j0 = det J0 at the element centre, j(xi) = det J(xi). Since the Gauss rule sums
/// xi_m to zero, int G_m dV = j0 J0^-T sum_g dM_m/dxi(xi_g) = 0: a homogeneous F (alpha = 0) leaves
/// the enhanced residual h = int P : (alpha (x) G) dV zero, so the patch test holds exactly, at
/// finite strain, on any mesh with det J > 0 at the Gauss points.
///
/// The alpha_m enter F exactly like three extra nodes' displacements, so the element is the
/// 33-dof Total Lagrangian element of tl_point.hpp. For given node displacements u the 9
/// parameters are found by Newton on h(u, alpha) = 0 from alpha = 0 (each evaluation starts there,
/// so F_int is a function of u alone: no state to store, to roll back when a step is cut, or to
/// checkpoint), and condensed:
///   K_T = K_uu - K_ua K_aa^-1 K_au,   F_int = f_u - K_ua K_aa^-1 h  (h ~ 0 at convergence),
/// the exact derivative of F_int(u) = f_u(u, alpha(u)) (implicit function theorem). The nodal
/// masses are those of the hex8: the modes carry none (condensed quasi-statically).
#include "solid/hex/hex8_element.hpp"

namespace tetfsi::solid::hex {

/// Internal force, condensed tangent and strain energy of one enhanced element (arguments as
/// hex8_evaluate). @param alpha out (optional): the converged mode amplitudes, row m = alpha_m [m].
/// @return DegenerateReference if det J <= 0 at a Gauss point or the centre; Inverted if det F <= 0
///         at a Gauss point or the local Newton on alpha does not converge in 30 iterations
ElementStatus hex8_enhanced_evaluate(const Material& m, const Matrix83d& X, const Matrix83d& u, Vector24d* f,
                                     Matrix24d* K, double* energy, Eigen::Matrix3d* alpha = nullptr);

/// F and S averaged over the Gauss points (volume-weighted) with the enhanced F, for output.
bool hex8_enhanced_average_stress(const Material& m, const Matrix83d& X, const Matrix83d& u, Eigen::Matrix3d& F,
                                  Eigen::Matrix3d& S);

}  // namespace tetfsi::solid::hex
