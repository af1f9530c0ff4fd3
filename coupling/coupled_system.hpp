#pragma once
/// @file coupled_system.hpp
/// The simultaneous fluid-solid system of Chentanez et al. 2006, eq. (7), as tetfsi assembles it.
///
/// With nodal (P1) fluid pressures p and solid nodal velocities u^{n+1}, eq. (7) reads
///
///     [ A    -J       ] [u]   [ b  ]            J  = Hᵀ
///     [ H    (h/ρ) L  ] [p] = [ r  ]            r  = Gᵀ V v*   (weak divergence of v*)
///
///  - A = M/h + C + (h/2) K′   (eq. 4), n x n, symmetric positive definite for a stable step;
///  - b = (M/h) uⁿ − (h/2) K′ uⁿ − K(dⁿ) + f_e   (eq. 4);
///  - H, m x n: (H u)_i = ∫_Γ φ_i (u · n) dA over the interface triangles Γ, n pointing out of
///    the fluid: the flux the solid imposes on pressure node i (the −D₁H term of eq. 6);
///  - J = Hᵀ: nodal forces of the pressure, f_a = ∫_Γ φ_a p n dA. Taking J and H from the same
///    quadrature makes the pressure's work on the solid equal the flux work on the fluid;
///  - L = Gᵀ V G, m x m, the P1 pressure Laplacian (symmetric positive semi-definite), so that
///    (h/ρ) L is the D₂G block of eq. (6) up to the sign of the weak divergence.
///
/// Negating the second row gives the symmetric quasi-definite form
///     [ A  −Hᵀ ; −H  −P ],  P = (h/ρ) L,
/// whose Schur complement on the pressure, S = P + H A⁻¹ Hᵀ, is symmetric positive definite:
/// the basis of the fast path (coupling/solvers/schur_cg_solver.cpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace tetfsi::coupling {

using SparseMatrix = Eigen::SparseMatrix<double>;

struct CoupledSystem {
  SparseMatrix A;     ///< n x n solid block of eq. (4) [kg/s]
  SparseMatrix H;     ///< m x n interface flux map [m²]
  SparseMatrix P;     ///< m x m pressure block (h/ρ) L [m⁴ s / kg] (not C: that is eq. 4's damping)
  Eigen::VectorXd b;  ///< n, solid right-hand side [N]
  Eigen::VectorXd r;  ///< m, weak divergence of the intermediate fluid velocity [m³/s]

  int num_solid_dofs() const { return static_cast<int>(A.rows()); }
  int num_pressures() const { return static_cast<int>(P.rows()); }
  /// Throws std::invalid_argument naming the block whose size does not match.
  void check_sizes() const;
};

/// Relative residuals of a candidate solution, one per block row of eq. (7):
///   solid:  ‖A u − Hᵀ p − b‖ / max(‖b‖, ‖A u‖, ‖Hᵀ p‖)
///   fluid:  ‖H u + P p − r‖ / max(‖r‖, ‖H u‖, ‖P p‖)
/// Each block is measured in its own units, so neither hides the other.
struct BlockResiduals {
  double solid = 0;
  double fluid = 0;
  double max() const { return solid > fluid ? solid : fluid; }
};
BlockResiduals residuals(const CoupledSystem& system, const Eigen::VectorXd& u, const Eigen::VectorXd& p);

/// The unsymmetric matrix of eq. (7) as written in the paper, [A −Hᵀ; H P], (n+m) x (n+m).
SparseMatrix paper_form_matrix(const CoupledSystem& system);

}  // namespace tetfsi::coupling
