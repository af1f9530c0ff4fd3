#pragma once
/// @file mpm_solver.hpp
/// Explicit MPM of Lian, Liu & Zhang (2014), sections 3 and 6, in the update-stress-first (USF)
/// form of their algorithm: per step
///   (60)-(61) map mass and momentum p^{n-1/2} to a freshly zeroed grid, apply grid conditions;
///   (62)-(63) strain increment and spin from the grid velocities, stress update (22, 25, 26);
///   (17)-(18) nodal internal and external forces; (64) trial momentum p^{n+1/2} = p^{n-1/2} + h f;
///   [contact may modify p^{n+1/2} here, eq. 53]
///   (65) particle velocity v += h sum_I (f_I + f^c_I) N_Ip / m_I, written as
///        sum_I N_Ip (p_I^{n+1/2} - p_I^{n-1/2}) / m_I so grid conditions and contact enter alike;
///   (19) particle position x += h sum_I N_Ip p_I^{n+1/2} / m_I.
/// Momentum is conserved to round-off, also when a particle sits exactly on a node plane: the
/// corners beyond it then have N_I = 0 but N_I,j != 0, and if they have no mass the particle's
/// stencil is closed (close_stencil: their gradients moved onto the corners with mass) so that no
/// force goes to a node no particle takes it back from and an empty node's zero velocity is not
/// read as strain.
/// Variable steps as in section 3.2: h^{n+1/2} is the step being taken (positions, eq. 19),
/// momentum advances by h^n = (h^{n-1/2} + h^{n+1/2}) / 2 (eq. 64), and the strain increment of
/// eq. (62) uses h^{n-1/2} (see mpm_solver.cpp). The first step takes h^{-1/2} = h^{1/2}.
///
/// Parallelism and determinism: the particle-to-grid sums (eqs. 60, 61 and 17) are taken per cell
/// (cell_moments.hpp), cells in parallel, each cell's particles in bin order; each node then sums
/// its cells' corner values in a fixed order, so results are bit-identical whatever the number of
/// threads. The grid-to-particle update (eqs. 65, 19) also runs cell by cell (its reductions are
/// exact max / min). Node loops cover only the box of occupied cells. The other reductions (contact
/// work, energies) use tbb::parallel_deterministic_reduce with a fixed grain. The cell bins are
/// kept from one step to the next while no particle leaves its cell; write access through
/// particles() makes the next step bin afresh.
#include <limits>
#include <vector>

#include "mpm/particles/cell_bins.hpp"
#include "mpm/particles/cell_moments.hpp"
#include "mpm/particles/grid.hpp"
#include "mpm/particles/material.hpp"
#include "mpm/particles/particles.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

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
  ///         mass or density, a non-symmetric stress, or a particle outside the grid
  MpmSolver(Grid grid, std::vector<Material> materials, Particles particles, MpmOptions options = {});

  const Grid& grid() const { return grid_; }
  const Particles& particles() const { return particles_; }
  /// Write access to the particles (the solver then bins them afresh at the next step). Do not keep
  /// the reference across steps: a write through a kept reference after the next step would go
  /// unnoticed by the cell bins, which are reused while no particle leaves its cell.
  Particles& particles() {
    bins_current_ = false;
    return particles_;
  }
  const std::vector<Material>& materials() const { return materials_; }
  const MpmOptions& options() const { return options_; }

  /// Critical step of eq. (21): cfl * min_p dx / (c_p + |v_p|), further limited by the explicit
  /// viscous bound rho dx^2 / (8 mu) for viscous fluids. Evaluated for the current state (at the
  /// end of each step, within the particle update). For elastic solids c_p + |v_p| is taken per
  /// cell as sqrt((lambda + 2 G) / rho_min) + |v|_max over the cell's particles (a bound above
  /// the exact value by at most the spread of |v| within a cell, to an ulp of the square root).
  /// Infinite without particles.
  double critical_time_step() const { return critical_h_; }

  /// Steps (60)-(64) for the step h = h^{n+1/2}: trial grid momentum. After this call
  /// node_momentum() holds p^{n+1/2}.
  void trial_step(double h);
  /// h^n = (h^{n-1/2} + h^{n+1/2}) / 2 of the current step (valid after trial_step): the factor
  /// between a nodal force and its momentum change (eqs. 53, 64, 65).
  double momentum_step() const { return h_n_; }
  /// Adds a contact impulse dp [N s] to the trial momentum p^{n+1/2} of `node` (eq. 53); the
  /// components held by the grid conditions are dropped. Between trial_step and finish_step.
  void add_node_impulse(std::int64_t node, const Vec3& dp);
  /// Steps (65) and (19) with the grid momentum p^{n+1/2} plus the impulses.
  /// @throws std::runtime_error if a particle state becomes non-finite or leaves the grid,
  ///         std::invalid_argument if h is not the step passed to trial_step
  void finish_step(double h);
  /// trial_step + finish_step.
  /// Checkpoints (mpm_solver_state.cpp): the state the steps change, bit for bit; read into an object set up
  /// from the same scene. @throws BinaryReadError
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);
  void step(double h);

  // Grid state of the current step (valid after trial_step; zero outside the occupied box).
  const std::vector<double>& node_mass() const { return mass_; }
  /// Trial momentum p^{n+1/2} of eq. (64), without the impulses.
  const std::vector<Vec3>& node_momentum() const { return mom_new_; }
  const std::vector<Vec3>& node_momentum_old() const { return mom_old_; }
  /// The particles binned by cell at the start of the current step (valid until finish_step).
  const CellBins& bins() const { return bins_; }
  /// Momentum the particles would carry to each of `nodes` after the trial update without
  /// contact: p~_I = sum_p m_p N_Ip (v_p + sum_J N_Jp (p_J^{n+1/2} - p_J^{n-1/2}) / m_J), written
  /// to out[I] (a node-indexed array of the grid's size; other entries are left alone). It differs
  /// from the grid trial momentum p_I^{n+1/2} by the consistent-versus-lumped mass difference of
  /// the FLIP update (65); an impulse computed from p~ changes the particles' kinetic energy by at
  /// most what it changes the grid's (see mpm/contact/grid_contact.hpp). Visits only the
  /// particles of the cells around the nodes. If `mass_gradient` is given, it also receives
  /// n_I^s = sum_p N_Ip,i m_p (eq. 51), the (unnormalised) outward normal of the particle body, at
  /// the same nodes (computed here, where contact needs it, rather than scattered by every
  /// particle in the mass pass).
  void particle_trial_momenta(const std::vector<std::int64_t>& nodes, std::vector<Vec3>& out,
                              std::vector<Vec3>* mass_gradient = nullptr);
  /// The occupied cells around `nodes` (each node lies in up to 8 cells) as (i, j, k), unique and in
  /// ascending global cell index (valid after trial_step, until the next call).
  const std::vector<std::array<int, 3>>& cells_around(const std::vector<std::int64_t>& nodes);
  /// Work of the impulses of the last finish_step on the particles [J]:
  /// sum_p m_p dv_p . (v_p^{n-1/2} + v_p^{n+1/2}) / 2, dv_p = sum_I N_Ip d_I / m_I the impulse part
  /// of eq. (65) (mid-step velocity, as the kinetic energy change of the whole step splits).
  double impulse_work() const { return impulse_work_; }
  /// Node components held at zero by the grid conditions.
  const std::vector<std::array<bool, 3>>& constraint_mask() const { return mask_; }
  /// Nodes with mass below this threshold are treated as empty.
  double mass_threshold() const { return mass_eps_; }

  MpmEnergies energies() const;
  Vec3 total_momentum() const;
  double time() const { return time_; }
  long steps() const { return steps_; }

 private:
  /// Coefficients of the velocity gradient of the trilinear field in one cell, a bilinear function
  /// of the position in the cell (see mpm_solver.cpp).
  using CellGradient = std::array<double, 36>;
  /// The coefficients of `cell` (global (i, j, k)) from this phase's node velocities vel_; returns
  /// whether some corner of the cell has no mass.
  bool cell_gradient(const std::array<int, 3>& cell, CellGradient& G) const;
  /// L_ij = sum_I v_iI N_I,j of a particle (in-cell position f) from its cell's coefficients.
  /// (Inline, defined in mpm_solver.cpp, its only user: called once per particle and step.)
  inline Mat3 velocity_gradient(const double f[3], const CellGradient& G) const;
  /// Index in the box of occupied cells of cell (i, j, k) (valid after trial_step's binning).
  std::size_t box_cell(const std::array<int, 3>& c) const {
    const auto& lo = bins_.lo();
    const auto& hi = bins_.hi();
    const std::size_t ex = hi[0] - lo[0] + 1, ey = hi[1] - lo[1] + 1;
    return std::size_t(c[0] - lo[0]) + ex * ((c[1] - lo[1]) + ey * (c[2] - lo[2]));
  }
  /// For each node (i, j, k), i in the box, of one row of the node box (`first`: node id of its
  /// first node): store(node id, sum) with sum = zero + value(box cell, corner of the node in that
  /// cell) over the node's (up to 8) occupied cells, in a fixed order per node.
  template <class T, class Value, class Store>
  void gather_row(int j, int k, std::int64_t first, const T& zero, Value&& value, Store&& store) const;
  /// Replaces the gradients of a stencil whose far corners have no mass (particle on a cell face)
  /// by N_I,j + N_I sum_{J empty} N_J,j on the corners with mass and 0 on the empty ones (see
  /// mpm_solver.cpp). Needs this step's node masses.
  void close_stencil(Stencil& st) const;
  /// Stress, density and energy update of particle p (eqs. 22-26) with its velocity gradient L;
  /// returns its new volume m / rho.
  /// (Forced inline, defined in mpm_solver.cpp, its only user: 5% faster than a call per particle.)
  __attribute__((always_inline)) inline double update_particle_stress(std::size_t p, double h, const Mat3& L);
  /// Zeroes mass, momenta and force of the nodes of the box [lo, hi] (the previous step's node box)
  /// that lie outside the current node box.
  void reset_nodes_outside_box(const std::array<int, 3>& lo, const std::array<int, 3>& hi);
  /// Calls f(first, j, k) for every row (j, k) of the node box (first: id of its first node), rows
  /// in parallel (one writer per row).
  template <class F>
  void for_each_box_row(F&& f) const;
  /// Calls f(id) for every node of the box of occupied cells (in parallel, one writer per node).
  template <class F>
  void for_each_box_node(F&& f) const;
  void check_particles(double h) const;

  Grid grid_;
  std::vector<Material> materials_;
  std::vector<std::array<double, 3>> lame_;  // per material: lambda, 2 G, lambda + 2 G [Pa]
  std::vector<double> inv_rho0_;              // per material: 1 / rho0
  std::vector<std::uint8_t> elastic_;         // per material: linear elastic (a solid)
  std::vector<double> inv_p_modulus_;         // per material: 1 / (lambda + 2 G) of a solid
  Particles particles_;
  MpmOptions options_;
  std::vector<std::array<bool, 3>> mask_;
  CellBins bins_;
  bool bins_current_ = false;  // the last finish_step left every particle in its cell: bins_ hold
  std::array<int, 3> box_lo_{0, 0, 0}, box_hi_{-1, -1, -1};  // node box of the current step
  std::vector<double> mass_;
  std::vector<Vec3> mom_old_, mom_new_, force_, impulse_;
  std::vector<Vec3> vel_, dvel_, dvel_imp_;  // per-node grid velocities of the current phase
  std::vector<double> work_;                 // per particle: impulse work of the last finish_step
  std::vector<CornerValues> cell_corners_;  // per cell of the box: corner masses and momenta, then forces
  struct StepBounds {  // reductions of the grid-to-particle update, per cell
    double c_max = 0;  // largest c + |v| (eq. 21)
    double h_viscous = std::numeric_limits<double>::infinity();  // smallest viscous bound
    std::size_t bad = std::numeric_limits<std::size_t>::max();  // first invalid particle
    bool moved = false;  // some particle left its cell
  };
  std::vector<StepBounds> cell_bounds_;
  std::vector<std::uint8_t> cell_stress_bad_;  // per cell of the box: a non-finite stress moment
  std::vector<double> visc_factor_;      // per material: dx^2 / (8 mu), infinite if not viscous
  std::vector<std::int64_t> impulse_nodes_;
  std::vector<std::uint8_t> cell_mark_;        // per cell of the box: flags of cells_around
  std::vector<std::array<int, 3>> around_;     // result of cells_around
  std::vector<std::array<double, 48>> around_acc_;  // per cell of around_: corner sums of particle_trial_momenta
  std::vector<std::uint8_t> marked_;  // node flags of particle_trial_momenta
  double mass_eps_ = 0;
  double critical_h_ = 0;
  double impulse_work_ = 0;
  double h_prev_ = 0;  // h^{n-1/2}: the last step taken (0 before the first)
  double h_n_ = 0;     // h^n of the current step
  double h_step_ = 0;  // h^{n+1/2} passed to trial_step
  double time_ = 0;
  long steps_ = 0;
};

}  // namespace tetfsi::mpm
