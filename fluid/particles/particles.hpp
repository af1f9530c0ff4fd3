#pragma once
/// @file particles.hpp
/// Velocity carried on particles (fluid.advection "apic" or "flip"; fluid/README.md, "Particles"):
/// the mesh keeps its roles (pressure at the nodes, one velocity v_t per tet, the projection, the
/// level set), and each step the velocity reaches the new mesh through particles instead of a
/// back-trace of the mesh field:
///
///   1. the particles move through the old mesh's velocity (RK2, particle_motion.hpp), are found
///      in the new mesh (point_locator.hpp) and kept in the fluid and in the liquid (phi < 0),
///   2. reseeding keeps each liquid tet populated (seeding.hpp),
///   3. P2G: v_t from the particles in tet t (transfer.hpp),
///   4. the solver adds sources, viscosity, body forces and the pressure (the grid step),
///   5. G2P: the particles take the new velocity (APIC, PIC) or its change (FLIP) (transfer.hpp).
///
/// The particles live in space, not on the mesh: a remeshed or moved mesh finds them anew.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace tetfsi::fluid {

/// The particle transfer (fluid.advection): none (the mesh advection of semi_lagrangian.hpp),
/// APIC (Jiang et al. 2015) or the FLIP/PIC blend (Zhu & Bridson 2005).
enum class ParticleTransfer { kNone, kApic, kFlip };

/// The particle settings of a fluid (scene: fluid.advection, fluid.flip_ratio, fluid.particles_per_tet).
struct ParticleOptions {
  ParticleTransfer transfer = ParticleTransfer::kNone;
  /// FLIP share r of the blend v_p = (1 - r) v_PIC + r v_FLIP (Zhu & Bridson 2005, sec. 4; r = 0: PIC).
  double flip_ratio = 0.97;
  /// Particles aimed at per tet full of liquid (a tet cut by the surface: that times its liquid
  /// fraction); reseeding adds below 2/3 of it and deletes above 4/3 of it (seeding.hpp).
  int per_tet = 6;

  bool enabled() const { return transfer != ParticleTransfer::kNone; }
};

/// The particles of a fluid, in the order of the tets that hold them (ascending `tet`).
struct ParticleSet {
  std::vector<Eigen::Vector3d> x;        ///< positions x_p [m]
  std::vector<Eigen::Vector3d> v;        ///< velocities v_p [m/s]
  /// APIC's affine velocity gradient per particle, Jiang et al. 2015's C_p (here ∇v_p: C is the
  /// damping matrix in docs/notation.md) [1/s]; empty for FLIP.
  std::vector<Eigen::Matrix3d> grad_v;
  std::vector<int> tet;                  ///< fluid tet of the current mesh holding x_p
  std::uint64_t seed_count = 0;          ///< reseedings so far (the key of their random numbers)

  int size() const { return static_cast<int>(x.size()); }
  /// Keeps the particles whose keep[p] is nonzero, in order.
  void keep_only(const std::vector<char>& keep);
  /// Reorders the particles by ascending tet (stable: equal tets keep their order).
  void sort_by_tet(int num_tets);
  /// first[t] .. first[t + 1] - 1: the particles of tet t (sorted by tet).
  std::vector<int> tet_ranges(int num_tets) const;
};

}  // namespace tetfsi::fluid
