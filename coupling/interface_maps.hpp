#pragma once
/// @file interface_maps.hpp
/// The interface maps H and J of Chentanez et al. 2006, §3.4, for nodal (P1) fluid pressures and
/// P1 solid velocities on the triangles that fluid and solid share.
///
/// On an interface triangle T (area A_T, unit normal n_T pointing out of the fluid, into the solid)
/// both the pressure and the solid velocity are linear, with the same three vertices. Then
///
///   flux into pressure node i:   (H u)_i = Σ_T ∫_T φ_i (u · n_T) dA = Σ_T Σ_a M^T_ia (n_T · u_a)
///   force on solid node a:       f_a     = Σ_T ∫_T φ_a p n_T dA     = Σ_T Σ_i M^T_ai p_i n_T
///
/// with the exact P1 triangle mass matrix M^T_ia = ∫_T φ_i φ_a dA = (A_T / 12)(1 + δ_ia).
/// For a liquid with a free surface the pressure lives on the wet part only, with the cut hats ψ_i
/// of fluid/liquid/cut_tet.hpp: M^T_ia = ∫_{T wet} ψ_i φ_a dA (InterfaceTriangle::mass). Then a
/// solid moving rigidly with the liquid has the flux Σ_a M^T_ia n_T·u = n_T·u ∫_{T wet} ψ_i dA that
/// the liquid's weak divergence (free_surface_projection.hpp) has for the same velocity; the full
/// P1 mass on a partly wet triangle counted the dry part's flux too, and a falling container
/// sucked its liquid out through its wall (tetfsi issue 15).
/// Both come from the same quadrature, so J = Hᵀ exactly: the work the pressure does on the solid,
/// pᵀ H u, equals the flux work on the fluid.
/// Consequences tested in tests/coupling: a hydrostatic pressure ρ g (z₀ − z) gives the buoyancy
/// ρ g V of Archimedes to round-off, and u(x) = ε x gives the flux ε ∮ x·n dA = 3εV.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

namespace tetfsi::coupling {

/// One triangle shared by a fluid tet and a solid tet.
struct InterfaceTriangle {
  std::array<int, 3> vertices;   ///< mesh vertex indices
  Eigen::Vector3d area_normal;   ///< A_T n_T, n_T pointing out of the fluid into the solid [m²]
  /// M^T_ia / A_T, row i the pressure's test function, column a the solid's hat: the P1 mass
  /// (1 + δ_ia) / 12 unless the triangle is cut by a liquid's surface, where the pressure hats are
  /// the liquid's cut hats on the wet part (fluid::wet_face_mass).
  std::array<std::array<double, 3>, 3> mass{{{2.0 / 12, 1.0 / 12, 1.0 / 12},
                                             {1.0 / 12, 2.0 / 12, 1.0 / 12},
                                             {1.0 / 12, 1.0 / 12, 2.0 / 12}}};
};

/// Where each mesh vertex's unknowns live (both sized #mesh vertices; -1 where none).
struct InterfaceDofs {
  std::vector<int> pressure_index;  ///< pressure unknown of the vertex, -1 if none (e.g. p = 0 prescribed)
  std::vector<int> solid_node;      ///< node of the solid's velocity vector u, -1 if not a solid node
};

/// Assembles H, num_pressures x 3 num_solid_nodes, with solid dofs ordered [x0 y0 z0 x1 ...].
/// J = Hᵀ. Vertices without a pressure unknown contribute no row; a triangle vertex that is not a
/// solid node is an error (the interface must lie on the solid).
/// @throws std::invalid_argument naming the triangle and vertex on inconsistent input
Eigen::SparseMatrix<double> interface_flux_map(const std::vector<InterfaceTriangle>& triangles,
                                               const InterfaceDofs& dofs, int num_pressures,
                                               int num_solid_nodes);

}  // namespace tetfsi::coupling
