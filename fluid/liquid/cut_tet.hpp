#pragma once
/// @file cut_tet.hpp
/// Geometry of a tetrahedron cut by the zero set of a level set phi that is linear on it
/// (P1, nodal values). Liquid is phi < 0, air phi >= 0.
///
/// The free-surface projection (free_surface_projection.hpp) integrates only over the liquid part
/// Omega_t of each tet. Its pressure trial and test functions are the hats psi_k of the liquid
/// nodes on the liquid part, linear between a liquid node and the points where the tet's edges
/// cross the surface, where they vanish (p = 0 on the surface, located to second order). What the
/// projection needs per tet is
///
///   |Omega_t|                                       (the liquid volume), and
///   a_k = int_{Omega_t} grad psi_k dV = sum_{faces F of t, k in F} n_F int_{F wet} psi_k dA
///
/// (divergence theorem; psi_k = 0 on the free surface, so only the wet parts of the tet's faces
/// contribute). On a tet with no air node a_k = V_t grad(phi_k), the ordinary P1 hat gradient times
/// the volume. A linear pressure that vanishes on the (planar) surface piece is reproduced exactly:
/// sum_k a_k p_k = |Omega_t| grad p.
///
/// Edge crossing: on an edge from liquid node a to air node b the surface lies at
/// x_a + theta_ab (x_b - x_a) with theta_ab = phi_a / (phi_a - phi_b), in (0, 1].
#include <Eigen/Core>
#include <array>

namespace tetfsi::fluid {

/// Where the edge from liquid node value phi_a (< 0) to air node value phi_b (>= 0) crosses zero,
/// as a fraction of the edge from a: theta = phi_a / (phi_a - phi_b).
inline double crossing_fraction(double phi_a, double phi_b) { return phi_a / (phi_a - phi_b); }

struct CutTet {
  double liquid_volume = 0.0;                   ///< |Omega_t| [m^3]
  std::array<Eigen::Vector3d, 4> wet_moment{};  ///< a_k [m^2]; zero for air nodes
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();  ///< int_{Omega_t} x dV [m^4] (gravity potential)
};

/// Liquid part of tet (x, phi). Where a face has two liquid nodes, psi_k on its wet quadrilateral
/// is the mean of its piecewise-linear interpolants on the quad's two splits into triangles: a
/// function of the face's own nodes and values, so both tets sharing the face agree, and with no
/// preference for either diagonal, so the projection does not depend on how the nodes are numbered
/// (a mirrored mesh gives the mirrored operator; splitting along the diagonal from the lower id, as
/// before, made the nodes with lower ids take more of each quad, and the node numbering follows a
/// space-filling curve from the low corner of the box). Either split reproduces a linear pressure
/// that vanishes on the planar surface, so their mean does. x must be positively oriented.
CutTet cut_tet(const std::array<Eigen::Vector3d, 4>& x, const std::array<double, 4>& phi);

/// Mass matrix of a triangle face F of a cut tet on its wet part, per unit face area:
/// M_ka = (1/A_F) int_{F wet} psi_k phi_a dA, psi_k the liquid hats of cut_tet (zero for an air
/// node k), phi_a the ordinary P1 hats of the face's vertices. The wet part is split as in cut_tet
/// (one liquid node: the corner triangle; two: the quadrilateral, the mean over its two splits),
/// and on each wet sub-triangle S both factors are linear, so the exact P1 rule applies:
/// int_S f g dA = (A_S / 12) (sum_j f_j g_j + (sum_j f_j)(sum_j g_j)) over its vertices j.
/// Consequences: sum_a M_ka = (1/A_F) int_{F wet} psi_k dA, the face's share of a_k in cut_tet;
/// all wet gives (1 + delta_ka) / 12. The coupled system's interface flux map uses it
/// (coupling/interface_maps.hpp), so that a solid face moving with the liquid carries the same
/// flux in H as in the liquid's weak divergence.
std::array<std::array<double, 3>, 3> wet_face_mass(const std::array<double, 3>& phi);

/// First moment of the liquid part, int_{Omega_t} x dV [m^4], exact for phi linear on the tet:
/// the liquid part split into tets (a corner, a tet less a corner, or a prism of three tets), each
/// contributing its volume times its centroid. x must be positively oriented.
Eigen::Vector3d liquid_first_moment(const std::array<Eigen::Vector3d, 4>& x, const std::array<double, 4>& phi);

/// Volume fraction |Omega_t| / V_t of the liquid (phi < 0) in a tet with nodal values phi, for
/// phi linear on the tet (exact).
double liquid_fraction(const std::array<double, 4>& phi);

}  // namespace tetfsi::fluid
