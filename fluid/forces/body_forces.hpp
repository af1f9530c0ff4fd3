#pragma once
/// @file body_forces.hpp
/// Accelerations added per tet between advection and projection.
#include <Eigen/Core>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"

namespace tetfsi::fluid {

/// Boussinesq smoke buoyancy (Fedkiw, Stam, Jensen 2001, "Visual simulation of smoke", eq. 8):
///   a_t = (-alpha s_t + beta (T_t - T_ambient)) * up,   up = -g / |g|
/// Smoke makes the fluid heavier (alpha), heat lighter (beta).
struct BuoyancyParams {
  double alpha = 0.0;                ///< [m/s^2 per unit smoke density]
  double beta = 0.0;                 ///< [m/s^2 per K]
  double ambient_temperature = 0.0;  ///< T_ambient [K]
};

/// u_t += h * a_t for the buoyancy above. `gravity` only gives the direction (zero: no buoyancy).
void add_buoyancy(const FluidMesh& mesh, const Eigen::VectorXd& smoke, const Eigen::VectorXd& temperature,
                  const Eigen::Vector3d& gravity, const BuoyancyParams& params, double h, TetVectors& u);

/// Vorticity confinement (Fedkiw et al. 2001 eqs. 9-11): omega_t = curl of the P1 interpolant of the
/// node-averaged velocity, N = grad|omega| / |grad|omega||, a_t = epsilon h_t (N x omega_t) with
/// h_t = V_t^(1/3). u_t += h a_t. epsilon is dimensionless; 0 disables it.
void add_vorticity_confinement(const FluidMesh& mesh, double epsilon, double h, TetVectors& u);

/// Per-tet vorticity curl(u) [1/s] of the P1 interpolant of the node-averaged velocity.
TetVectors vorticity(const FluidMesh& mesh, const TetVectors& u);

}  // namespace tetfsi::fluid
