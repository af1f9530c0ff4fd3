#pragma once
/// @file grid_contact.hpp
/// Contact between an MPM body s and a membrane body r on the MPM background grid
/// (Lian, Liu & Zhang 2014, sections 5 and 6):
///   1. trial solutions of both bodies (MPM eqs. 60-64, membrane eq. 46);
///   2. FE node masses and momenta mapped to the grid with the trilinear N_IK (step 4a);
///   3. at nodes carrying both bodies, contact if the momentum-form test (eq. 52)
///        (m_I^s p_I^r - m_I^r p_I^s) . n_I^r > 0
///      holds AND the bodies are really close there (the real-distance check of Ma, Zhang et al.
///      2010): the gap between the membrane (mass centre xbar_I^r of its points around I) and the
///      surface of the nearest particle p in the support of I (radius r_p = V_p^{1/3} / 2),
///        g_I = min_p (x_p - xbar_I^r) . n_I^r - r_p,
///      is below `distance_factor` * dx (so the membrane is stopped at most that far from the
///      particles, and false contacts one or two cells away are rejected);
///   4. stick force (eq. 55) or Coulomb slip (eqs. 56-58), f^s = -f^r;
///   5. MPM grid momentum += h f^s (eq. 53); membrane velocity += h sum_I N_IK f_I^r / m_I^r
///      (eq. 59), then membrane positions (eq. 47) and particles (eqs. 65, 19).
/// n_I^r is the sum of the membrane's area-weighted node normals mapped to the node (the membrane
/// is two-sided: it is oriented to point into body s, i.e. against the outward normal of eq. 51).
/// Sign: eq. (55) is printed as the force that would *increase* the approach; the force applied
/// to r here is f^r = -(m^s p^r - m^r p^s)/((m^r + m^s) h), which brings both to the common
/// velocity (p^r + p^s)/(m^r + m^s), i.e. eq. (54).
///
/// Particle-side momentum p_I^s (a deviation from the literal eqs. 52-55, which use the grid trial
/// momentum p_I^{n+1/2} of eq. 64): p_I^s = sum_p m_p N_Ip v~_p with v~_p the particle velocity
/// after the trial update (MpmSolver::particle_trial_momenta). The particles receive a grid
/// impulse d_I through eq. (65) as dv_p = sum_I N_Ip d_I / m_I, which changes their kinetic
/// energy by sum_I d_I . p_I^s / m_I + 1/2 sum_p m_p |dv_p|^2 <= sum_I (d_I . p_I^s + |d_I|^2 / 2)
/// / m_I (Jensen, sum_I N_Ip = 1); the same holds for the FE nodes with eq. (59). With p_I^s in
/// eqs. (52)-(58) the right-hand side is the grid-level change, which stick and Coulomb slip
/// can only lower. With p_I^{n+1/2} instead, the first term is not the particles' (FLIP maps
/// with the consistent mass, p_I^{n+1/2} carries the lumped one): the sphere-on-membrane case of
/// section 7.1 then gained 10% energy with slip contact, and 8x with distance_factor 1.0.
///
/// Energy bookkeeping: the work of the contact forces on each body is measured where its kinetic
/// energy lives, with the mid-step velocity as for the membrane's external loads:
/// W^r = sum_K m_K dv_K . (v_K^{n-1/2} + v_K^{n+1/2}) / 2 and the same over particles
/// (MpmSolver::impulse_work); the contact dissipation is -(W^r + W^s), so stored energy plus
/// dissipation is constant up to the explicit schemes' own error (0.2% over a gas expansion run).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "mpm/particles/mpm_solver.hpp"
#include "mpm/membrane/membrane.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

namespace tetfsi::mpm {

using Vec3 = Eigen::Vector3d;

struct ContactOptions {
  enum class Mode { Stick, Slip };
  Mode mode = Mode::Slip;
  double friction = 0.0;         ///< Coulomb coefficient mu of eq. (58) (slip mode)
  double distance_factor = 0.25;  ///< real-distance confirmation threshold, in cells
};

/// What the contact did in one step.
struct ContactReport {
  int contact_nodes = 0;
  Vec3 impulse_on_mpm = Vec3::Zero();       ///< h sum_I f_I^s [N s]
  Vec3 impulse_on_membrane = Vec3::Zero();  ///< h sum_I f_I^r [N s]
  /// Energy removed by the contact in this step [J]: -(work_on_membrane + work_on_mpm).
  double dissipated = 0;
  double work_on_membrane = 0;  ///< work of the contact forces on the FE nodes (eq. 59) [J]
  double work_on_mpm = 0;       ///< work of the contact impulses on the particles [J]
  // Wall time of the step's parts [s]: the particles' trial step (section 6 step 2: scatter,
  // stress, nodal forces), the membrane (step 3 and eq. 47), the contact (step 4), the particles'
  // update (step 5: grid to particles, eqs. 65, 19).
  double seconds_particle_trial = 0, seconds_membrane = 0, seconds_contact = 0, seconds_particle_update = 0;
};

/// Energies of the coupled system [J].
struct CoupledEnergies {
  mpm::MpmEnergies mpm;
  mpm::MembraneEnergies membrane;
  double contact = 0;  ///< accumulated contact dissipation
  /// kinetic + internal + gravity potential of MPM, kinetic + strain + hourglass of the membrane,
  /// minus the work of the membrane's external loads, plus contact and damping losses: constant
  /// for an exactly conservative scheme.
  double balance() const {
    return mpm.total() + membrane.kinetic + membrane.strain + membrane.hourglass - membrane.external_work +
           membrane.damping_loss + contact;
  }
};

class MpmMembraneCoupling {
 public:
  MpmMembraneCoupling(mpm::MpmSolver& mpm, mpm::Membrane& membrane, ContactOptions options = {});

  /// Smaller of the two critical steps (section 4.4).
  double critical_time_step() const;
  /// One coupled step of section 6.
  /// @throws std::runtime_error on non-finite states (from either body)
  /// Checkpoints (coupled_model_state.cpp): the state the steps change, bit for bit; read into an object set up
  /// from the same scene. @throws BinaryReadError
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in);
  ContactReport step(double h);

  CoupledEnergies energies() const;
  Vec3 total_momentum() const { return mpm_.total_momentum() + mem_.total_momentum(); }
  double time() const { return mpm_.time(); }

 private:
  mpm::MpmSolver& mpm_;
  mpm::Membrane& mem_;
  ContactOptions opt_;
  double contact_energy_ = 0;
  /// Grid fields of the membrane at one node, per step. One record per node (dense, like the MPM
  /// grid) so that the scattered per-node accesses of a step touch two cache lines, not one per
  /// field (the reset of five separate arrays was the costliest line of the contact step).
  struct MembraneAtNode {
    double m;   ///< membrane mass m^r_I
    Vec3 p;     ///< momentum p^r_I
    Vec3 n;     ///< sum of N_I n_k, then the unit normal oriented towards the particles (candidates)
    Vec3 x;     ///< sum of N_I m_k x_k (mass-weighted position)
    Vec3 f;     ///< contact force on the membrane (eq. 55 or 58)
    bool seen;  ///< in touched_
    static MembraneAtNode zero() { return {0.0, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), false}; }
  };
  std::vector<MembraneAtNode> at_;
  std::vector<Vec3> ps_;  // particle-side trial momentum at candidate nodes
  std::vector<Vec3> grad_s_;  // particle-body mass gradient n^s (eq. 51) at the shared nodes
  std::vector<std::array<double, 8>> cell_gap_;  // compute_gaps: per cell, the smallest gap per corner
  std::vector<std::int64_t> touched_, shared_, candidates_;
  // Per-step membrane buffers (kept to avoid allocations).
  std::vector<Vec3> normals_;
  std::vector<int> inside_;
  std::vector<mpm::Stencil> fe_st_;

  std::vector<double> gap_;  // NaN except at candidate nodes during a step
  /// Real-distance gaps [m] of the candidate nodes into gap_ (see the file comment).
  void compute_gaps();
};

}  // namespace tetfsi::mpm
