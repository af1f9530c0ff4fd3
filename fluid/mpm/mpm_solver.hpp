#pragma once
/// @file mpm_solver.hpp
/// Explicit MPM of Lian, Liu & Zhang (2014), sections 3 and 6, in the update-stress-first (USF)
/// form of their algorithm: per step
///   (60)-(61) map mass and momentum p^{n-1/2} to a freshly zeroed grid, apply grid conditions;
///   (62)-(63) strain increment and spin from the grid velocities, stress update (22, 25, 26);
///   (17)-(18) nodal internal and external forces; (64) trial momentum p^{n+1/2} = p^{n-1/2} + dt f;
///   [contact may modify p^{n+1/2} here, eq. 53]
///   (65) particle velocity v += dt sum_I (f_I + f^c_I) N_Ip / m_I, written as
///        sum_I N_Ip (p_I^{n+1/2} - p_I^{n-1/2}) / m_I so grid conditions and contact enter alike;
///   (19) particle position x += dt sum_I N_Ip p_I^{n+1/2} / m_I.
/// Momentum is conserved to round-off except when a particle sits exactly on a node plane: a node of
/// zero mass then receives a force (through N_I,j != 0 while N_I = 0) that no particle takes back.
/// A single dt per step is used for Delta t^n and Delta t^{n+1/2}.
///
/// Determinism: per-particle work (stencils, stress update, particle update) runs in TBB
/// parallel_for writing only to its own particle; the particle-to-grid scatters are serial so that
/// floating-point sums are always taken in the same order.
#include <vector>

#include "fluid/mpm/grid.hpp"
#include "fluid/mpm/material.hpp"
#include "fluid/mpm/particles.hpp"

namespace tetfsi::mpm {

struct MpmOptions {
  Vec3 gravity = Vec3::Zero();  ///< body force per unit mass f_ip of eq. (18) [m/s^2]
  double cfl = 0.5;             ///< safety factor on the critical step of eq. (21)
};

/// Energies of the particle body [J].
struct MpmEnergies {
  double kinetic = 0;   ///< sum 1/2 m_p |v_p|^2
  double internal = 0;  ///< fluids: E V0; solids: elastic strain energy 1/2 sigma:C^-1:sigma V
  double gravity = 0;   ///< - sum m_p g . x_p
  double total() const { return kinetic + internal + gravity; }
};

class MpmSolver {
 public:
  /// @throws std::invalid_argument on an empty material list, a bad material index, non-positive
  ///         mass or density, or a particle outside the grid
  MpmSolver(Grid grid, std::vector<Material> materials, Particles particles, MpmOptions options = {});

  const Grid& grid() const { return grid_; }
  const Particles& particles() const { return particles_; }
  Particles& particles() { return particles_; }
  const std::vector<Material>& materials() const { return materials_; }
  const MpmOptions& options() const { return options_; }

  /// Critical step of eq. (21): cfl * min_p h / (c_p + |v_p|), further limited by the explicit
  /// viscous bound rho h^2 / (8 mu) for viscous fluids.
  double critical_time_step() const;

  /// Steps (60)-(64): trial grid momentum. After this call node_momentum() holds p^{n+1/2}.
  void trial_step(double dt);
  /// Steps (65) and (19) with the (possibly contact-corrected) grid momentum.
  /// @throws std::runtime_error if a particle state becomes non-finite or leaves the grid
  void finish_step(double dt);
  /// trial_step + finish_step.
  void step(double dt);

  // Grid state of the current step (valid after trial_step).
  const std::vector<double>& node_mass() const { return mass_; }
  std::vector<Vec3>& node_momentum() { return mom_new_; }
  const std::vector<Vec3>& node_momentum() const { return mom_new_; }
  const std::vector<Vec3>& node_momentum_old() const { return mom_old_; }
  /// n_I^s = sum_p N_Ip,i m_p (eq. 51): the (unnormalised) outward normal of the particle body.
  const std::vector<Vec3>& node_mass_gradient() const { return mass_grad_; }
  /// Shape-function stencils of the particles at the start of the current step.
  const std::vector<Stencil>& stencils() const { return stencils_; }
  /// Re-applies the grid conditions to p^{n+1/2} (after a contact changed it).
  void apply_grid_conditions();
  /// Grid nodes with mass, ascending.
  const std::vector<std::int64_t>& active_nodes() const { return active_; }
  /// Node components held at zero by the grid conditions.
  const std::vector<std::array<bool, 3>>& constraint_mask() const { return mask_; }
  /// Nodes with mass below this threshold are treated as empty.
  double mass_threshold() const { return mass_eps_; }

  MpmEnergies energies() const;
  Vec3 total_momentum() const;
  double time() const { return time_; }
  long steps() const { return steps_; }

 private:
  void update_particle_stress(std::size_t p, double dt);

  Grid grid_;
  std::vector<Material> materials_;
  Particles particles_;
  MpmOptions options_;
  std::vector<std::array<bool, 3>> mask_;
  std::vector<Stencil> stencils_;
  std::vector<double> mass_;
  std::vector<Vec3> mom_old_, mom_new_, force_, mass_grad_;
  std::vector<Vec3> vel_, dvel_;  // per-node grid velocities of the current phase
  std::vector<std::int64_t> active_;
  double mass_eps_ = 0;
  double time_ = 0;
  long steps_ = 0;
};

}  // namespace tetfsi::mpm
