#pragma once
/// @file membrane.hpp
/// Explicit Belytschko-Tsay membrane (Lian, Liu & Zhang 2014, section 4): 4-node quads with
/// co-rotational frames (eqs. 32-39), one-point quadrature, strain rate (eqs. 40-41), nodal forces
/// (eqs. 42-45), plane-stress linear elastic law, Flanagan-Belytschko stiffness hourglass control,
/// central-difference time integration (eqs. 46-48).
///
/// Step structure (section 6, step 3): compute_forces(h) with x^n and v^{n-1/2} updates the stress
/// to t^n and assembles f^n; trial_velocities(h) gives v^{n+1/2} (eq. 46) with constraints; a
/// contact may then correct v (eq. 59); update_positions(h) gives x^{n+1} (eq. 47).
/// h is the step being taken, h^{n+1/2} (eq. 47); eq. (46) advances by h^n = (h^{n-1/2} +
/// h^{n+1/2}) / 2 and the strain increment uses h^{n-1/2} (section 3.2; equal for equal steps).
/// The strain rate of eq. (40) is evaluated on the mid-step geometry x^{n-1/2} = x^n - h/2 v^{n-1/2}
/// (evaluating it on x^n gained ~20% energy in 0.3 ms in a point-impact test; mid-step conserves it).
/// The thickness is kept constant (no thickness update).
#include <Eigen/Core>

#include <array>
#include <functional>
#include <vector>

#include "mpm/membrane/quad_frame.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

namespace tetfsi::mpm {

struct MembraneMaterial {
  double rho = 0;        ///< density [kg/m^3]
  double youngs = 0;     ///< E [Pa]
  double poisson = 0;    ///< nu [-]
  double thickness = 0;  ///< t [m]
  /// Flanagan-Belytschko stiffness coefficient eps_hg of the in-plane modes:
  /// k_e = eps_hg * E t / (1 - nu^2) * A (B_1.B_1 + B_2.B_2), fixed at the initial geometry.
  double hourglass = 0.1;
  /// Same coefficient for the out-of-plane (warping) hourglass mode. A membrane has no bending
  /// stiffness, so this is 0 unless asked for.
  double hourglass_normal = 0.0;
  /// @throws std::invalid_argument naming the bad parameter
  void validate() const;
  /// Plane-stress modulus E / (1 - nu^2).
  double plate_modulus() const { return youngs / (1 - poisson * poisson); }
};

/// Energies of the membrane [J].
struct MembraneEnergies {
  double kinetic = 0;
  double strain = 0;     ///< 1/2 sigma : C^-1 : sigma V per element
  double hourglass = 0;  ///< 1/2 |Q|^2 / k per element
  double external_work = 0;  ///< work done by pressure and gravity so far
  double damping_loss = 0;   ///< work removed by the optional mass-proportional damping
};

class Membrane {
 public:
  /// @param nodes initial positions; @param quads node ids, counter-clockwise about the normal.
  /// @throws std::invalid_argument on bad ids or material, std::runtime_error on degenerate quads
  Membrane(std::vector<Vec3> nodes, std::vector<std::array<int, 4>> quads, MembraneMaterial material);

  /// Holds component `axis` (0..2) of node `node` at zero velocity.
  void fix(int node, int axis);
  /// Fixes component `axis` of every node where `where(x)` holds (symmetry planes, clamped edges).
  int fix_where(const std::function<bool(const Vec3&)>& where, std::array<bool, 3> axes);
  /// Uniform pressure [Pa] acting along the deformed element normal e3 (follower load):
  /// f_K += p S_e / 4 with S_e the element vector area.
  void set_pressure(double p) { pressure_ = p; }
  void set_gravity(const Vec3& g) { gravity_ = g; }
  /// Mass-proportional damping coefficient c [1/s]: f_K -= c m_K v_K (for dynamic relaxation).
  /// Explicit, so it needs c h < 2.
  void set_damping(double c) { damping_ = c; }

  /// Eq. (48): cfl * min_e L_e / c, L_e = A_e / (longest side), c = sqrt(E / (rho (1 - nu^2))).
  double critical_time_step(double cfl = 0.9) const;

  void compute_forces(double h);
  /// Eq. (46) with h^n (the h argument is the step h^{n+1/2} passed to compute_forces).
  void trial_velocities(double h);
  /// h^n of the current step (valid after compute_forces): the factor between a nodal force and
  /// its velocity change m dv (eqs. 46, 59).
  double velocity_step() const { return h_n_; }
  /// @throws std::runtime_error if a node becomes non-finite
  void update_positions(double h);
  void step(double h);
  /// Checkpoints (membrane_state.cpp): positions, velocities, forces, stresses, hourglass forces,
  /// work bookkeeping and step lengths, bit for bit; read into a membrane made from the same scene
  /// (mesh, material, fixed components). @throws BinaryReadError
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);

  int num_nodes() const { return static_cast<int>(x_.size()); }
  int num_elements() const { return static_cast<int>(quads_.size()); }
  const std::vector<Vec3>& positions() const { return x_; }
  std::vector<Vec3>& positions() { return x_; }
  const std::vector<Vec3>& velocities() const { return v_; }
  std::vector<Vec3>& velocities() { return v_; }
  const std::vector<double>& masses() const { return mass_; }
  const std::vector<Vec3>& forces() const { return f_; }
  const std::vector<std::array<int, 4>>& quads() const { return quads_; }
  const std::vector<std::array<bool, 3>>& fixed() const { return fixed_; }
  const MembraneMaterial& material() const { return mat_; }
  /// Local stress (sigma_xx, sigma_yy, sigma_xy) of element e in its co-rotational frame [Pa].
  const Eigen::Vector3d& local_stress(int e) const { return stress_[e]; }
  /// Global Cauchy stress tensor q sigma_hat q^T of element e at the current geometry.
  Mat3 global_stress(int e) const;
  /// Area-weighted node normals sum_e S_e / 4 (unnormalised), for contact.
  std::vector<Vec3> node_normals() const;
  /// The same into `out` (resized; no allocation once it has the size).
  void node_normals(std::vector<Vec3>& out) const;
  MembraneEnergies energies() const;
  /// Work of the external loads (pressure, gravity) so far [J] (MembraneEnergies::external_work).
  double external_work() const { return ext_work_; }
  Vec3 total_momentum() const;

 private:
  std::vector<Vec3> x_, v_, f_;
  std::vector<double> mass_;
  std::vector<std::array<int, 4>> quads_;
  MembraneMaterial mat_;
  std::vector<std::array<bool, 3>> fixed_;
  std::vector<Eigen::Vector3d> stress_;  // local (xx, yy, xy)
  std::vector<Vec3> hg_force_;           // hourglass generalized forces Q (local x, y, z)
  std::vector<double> hg_k_;             // in-plane hourglass stiffness per element
  double pressure_ = 0, damping_ = 0;
  Vec3 gravity_ = Vec3::Zero();
  double ext_work_ = 0, damp_loss_ = 0;
  double h_prev_ = 0;  // h^{n-1/2}: the last step taken (0 before the first)
  double h_n_ = 0;     // h^n of the current step
  double h_step_ = 0;  // h^{n+1/2} passed to compute_forces
  std::vector<Vec3> f_ext_;  // external + damping part of f^n, for the work bookkeeping
  // Element corner forces of compute_forces and the node -> corner map that gathers them.
  std::vector<Vec3> corner_force_, pressure_force_;
  std::vector<int> node_start_, node_corner_;
};

}  // namespace tetfsi::mpm
