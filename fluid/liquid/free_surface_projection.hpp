#pragma once
/// @file free_surface_projection.hpp
/// Pressure projection of a liquid with a free surface, on the nodal-pressure / tet-velocity
/// scheme (Ando, Thuerey & Wojtan 2013, sec. 3) restricted to the liquid part of each tet.
///
/// The liquid is phi < 0 for a level set phi at the nodes (level_set.hpp); air is void: no air
/// pressure unknowns, p = 0 on the surface. On each tet t with liquid part Omega_t (cut_tet.hpp),
/// the pressure p_h = sum_k p_k psi_k is linear between the liquid nodes and the points where the
/// edges cross the surface, where it is zero, so the Dirichlet condition sits on the surface itself
/// (the ghost-fluid location of Gibou et al. 2002, J. Comput. Phys. 176, 205-227; in 1D this system
/// is exactly their symmetric ghost-fluid stencil). With the per-tet average pressure gradient
/// B_t p = (1/|Omega_t|) sum_k a_k p_k (a_k = int_{Omega_t} grad psi_k) and W = diag(|Omega_t|):
///
///   (h/rho) B^T W B p = B^T W u* - f      at every liquid node that is not open
///   u_t = u*_t - (h/rho) B_t p            on every tet with liquid
///
/// i.e. (B^T W B)_ij = sum_t a_i . a_j / |Omega_t|. This is the W-orthogonal projection of u* onto
/// the velocities whose flux through the wet parts of the dual cells vanishes: the weak divergence
/// (D u)_i = f_i - sum_t a_i . u_t is zero to solver tolerance at every liquid node, the liquid's
/// kinetic energy 1/2 rho sum_t |Omega_t| |u_t|^2 never grows in the projection, and B^T W B is
/// symmetric positive definite on every mesh (a sum of Gram matrices; each connected body of liquid
/// touches the surface or an open face, or is pinned at one node). A linear pressure that vanishes
/// on a planar surface is exact (still water stays still to round-off). Without air nodes it is
/// projection.hpp's system, term by term.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "fluid/boundary/boundary_conditions.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "fluid/projection/projection.hpp"

namespace tetfsi::fluid {

/// The liquid part of every fluid tet for one level set.
struct LiquidGeometry {
  std::vector<double> liquid_volume;                    ///< |Omega_t| per tet [m^3]
  std::vector<std::array<Eigen::Vector3d, 4>> wet_moment;  ///< a_k per tet and local node [m^2]
  std::vector<Eigen::Vector3d> first_moment;             ///< int_{Omega_t} x dV per tet [m^4]
  std::vector<char> is_liquid;                          ///< per node: phi < 0
  int num_air_nodes = 0;
  /// Total liquid volume sum_t |Omega_t| [m^3].
  double total_volume() const;
};

/// Cut-tet geometry of `mesh` for the nodal level set `phi` (cut_tet.hpp). Parallel, deterministic.
/// @throws std::invalid_argument if phi has not one value per node
LiquidGeometry liquid_geometry(const FluidMesh& mesh, const Eigen::VectorXd& phi);

/// Projects u in place (see file doc); the pressure is zero at air and open nodes.
/// ProjectionReport::max_divergence is max |(D u)_i| / dual_volume_i over the unknowns.
/// @throws std::invalid_argument on non-positive h or density, or sizes that do not match
/// @throws SolverError if the pressure solve fails
ProjectionReport project_free_surface(const FluidMesh& mesh, const ClassifiedBoundary& bc,
                                      const LiquidGeometry& liquid, double h, double density, TetVectors& u,
                                      const SolverOptions& options);

/// (sum_t a_i . u_t)_i at every node [m^3/s]: the weak divergence of u over the wet parts, without
/// the boundary flux (for the coupled system's fluid rows; all-liquid: G^T V u).
Eigen::VectorXd wet_gradient_transpose(const FluidMesh& mesh, const LiquidGeometry& liquid, const TetVectors& u);

/// B^T W B restricted to the nodes with unknown[i] >= 0 (numbered by unknown[], m of them):
/// (B^T W B)_ij = sum_t a_i . a_j / |Omega_t| [m]. Parallel assembly into fixed slots: deterministic.
Eigen::SparseMatrix<double> wet_laplacian(const FluidMesh& mesh, const LiquidGeometry& liquid,
                                          const std::vector<int>& unknown, int m);

/// u_t -= (h/rho) B_t p on every tet with liquid (the free-surface form of Chentanez et al. 2006
/// eq. 8), p per node (zero at air and open nodes).
void apply_wet_pressure(const FluidMesh& mesh, const LiquidGeometry& liquid, const Eigen::VectorXd& pressure,
                        double h, double density, TetVectors& u);

/// Kinetic energy of the liquid per unit density, 1/2 sum_t |Omega_t| |u_t|^2 [m^5/s^2].
double liquid_kinetic_energy(const LiquidGeometry& liquid, const TetVectors& u);

}  // namespace tetfsi::fluid
