#pragma once
/// @file closed_regions.hpp
/// The volume of closed fluid regions, kept over a run.
///
/// A closed region is a connected set of fluid tets with no node of prescribed pressure (no open
/// face, no air of a free surface) and no prescribed boundary flux (no inflow): its boundary is
/// fixed walls and solid interface triangles, so its volume
///
///     V(x) = (1/6) Σ_f x_a · (x_b × x_c)        over its boundary triangles f = (a, b, c),
///                                              oriented out of the fluid,
///
/// changes only with the solids, at the rate dV/dt = aᵀ u, where a = ∂V/∂x gathers (A_f n_f)/3
/// of every boundary triangle at each of its solid nodes: the column sums of H over the region's
/// rows (interface_maps.hpp, Σ_i M^T_ia = A_T/3). An incompressible fluid in such a region fixes
/// the solids' total volume change.
///
/// Eq. (7) of Chentanez et al. (2006) imposes aᵀ u^{n+1} = 0 on the step's start configuration
/// xⁿ, but both Newmark schemes move the solids by (h/2)(uⁿ + u^{n+1}) (eq. 5), and uⁿ met the
/// constraint on x^{n−1}, not on xⁿ (and contact changes uⁿ after its solve: the inelastic
/// normal, solid/integrator/newmark.hpp). So the region's volume moves by (h/2) aᵀuⁿ + O(h²)
/// per step and the error builds up: a soft ball in a closed tank of water lost 2.5–5.7% of its
/// volume over 1.5 s, and 41% in a hard landing. Per closed region with a moving boundary, two
/// corrections make V(x^{n+1}) = V₀ up to the quadratic term of one step's motion:
///
///  1. `project_start_velocity`: uⁿ ← uⁿ − M⁻¹ Σ_c a_c λ_c with Σ_d (a_cᵀ M⁻¹ a_d) λ_d = a_cᵀ uⁿ:
///     the M-orthogonal projection of the solids' velocity onto the velocities that keep every
///     closed volume (it only removes kinetic energy, (aᵀuⁿ)²/(2 aᵀM⁻¹a) for one region);
///     prescribed dofs are left alone (M⁻¹ = 0 there).
///  2. `volume_source`: a uniform dilatation of the region in eq. (7)'s fluid rows, r_i += w_i S_c
///     with w_i = V_i / Σ_{j ∈ c} V_j (dual volumes), so that summing the region's rows gives
///     aᵀ u^{n+1} = S_c, and with S_c = 2 (V₀ − V(xⁿ) − q̂)/h the step ends at
///     V(x^{n+1}) = V(xⁿ) + (h/2) aᵀ(uⁿ + u^{n+1}) + q = V₀ + q − q̂.
///     q is the part of the step's volume change that is not linear in the motion: a body turning
///     at ω is moved along the tangent of its rotation, x + h ω × x, which grows its volume by
///     (ω h)² V a step (the determinant of I + h [ω]×); a resting ball rocking in the water that
///     its landing set moving (1 rad/s at h = 1/30 s) gained 1e-5 of the tank's water volume this
///     way a step, 0.1% of its own. q̂ = V(xⁿ + h ū) − V(xⁿ) − h aᵀū predicts it with the projected
///     start velocity ū (`predict_motion`).
///
/// Without 1, the velocity u^{n+1} that 2 asks for would enter the next step's motion again and
/// the correction would flip sign every step; with both, the error left after a step is q − q̂.
///  3. Where that is still more than `tolerance` (an impact's step, whose motion the start
///     velocity does not predict), the step's solution is corrected by the responses (u_c, p_c) of
///     eq. (7) to each region's unit dilatation (b = 0, r = w_c; the same matrix, so the same
///     factor): u^{n+1} + Σ_c s_c u_c with the s_c that make V_c(x^{n+1}) = V₀_c, found by Newton
///     on the cubic V(x^{n+1}(s)) (CoupledStepper::restore_closed_volumes). The tolerance is
///     1e-4 of the smaller of V₀ and the volume of the solids around the region. Remeshing keeps a region's boundary, hence
/// V; V₀ is the region's volume the first time it is seen. Regions are matched from step to step
/// by the smallest solid node on their boundary (solid nodes keep their numbers).
#include <Eigen/Core>
#include <array>
#include <map>
#include <vector>

#include "fluid/boundary/boundary_conditions.hpp"
#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::coupling {

/// One closed fluid region of the current mesh.
struct ClosedRegion {
  int key = -1;                                ///< smallest solid node (system node id) on its boundary
  std::vector<int> nodes;                      ///< its fluid nodes
  std::vector<std::array<int, 3>> faces;       ///< boundary triangles, TetMesh vertex ids, out of the fluid
};

/// The closed regions of `fm` that have at least one solid node on their boundary.
/// @param unknown      fluid node -> pressure unknown, −1 where the pressure is prescribed (open, air)
/// @param bc           the boundary classification of fm (prescribed fluxes)
/// @param solid_node   TetMesh vertex -> system solid node id (dof / 3), −1 if not a solid node
std::vector<ClosedRegion> find_closed_regions(const fluid::FluidMesh& fm, const std::vector<int>& unknown,
                                              const fluid::ClassifiedBoundary& bc,
                                              const std::vector<int>& solid_node);

/// V(x) of the region with TetMesh vertices at x [m³] (the file comment's formula).
double region_volume(const ClosedRegion& region, const std::vector<Eigen::Vector3d>& x);

/// a = ∂V/∂x of the region at the solid dofs (3 per solid node, `num_solid_dofs` in all) [m²],
/// with TetMesh vertices at x; wall vertices do not move and get nothing.
Eigen::VectorXd region_volume_gradient(const ClosedRegion& region, const std::vector<Eigen::Vector3d>& x,
                                       const std::vector<int>& solid_node, int num_solid_dofs);

/// What the corrections did in one step (stats.csv).
struct ClosedVolumeReport {
  int regions = 0;           ///< closed regions with a moving boundary
  int resolves = 0;          ///< solves of correction 3 (one per region, in a step that needed it)
  double error = 0;          ///< (V(xⁿ) − V₀)/V₀ of the region where it is largest in size, before the step's correction
  double correction = 0;     ///< h S_c / V₀ of that region: the volume the step's source restores, relative
  double removed_kinetic = 0;  ///< kinetic energy the start-velocity projection removed [J]
};

/// The reference volumes and the two corrections of the file comment.
class ClosedVolumes {
 public:
  /// Finds this step's regions (find_closed_regions) with TetMesh vertices at x, keeps those with
  /// a free solid dof on their boundary (`fixed`: per solid dof, velocity prescribed; a region
  /// whose boundary is all walls and prescribed motion cannot be corrected), takes the reference
  /// volume of every region not seen before, and returns their count.
  int begin_step(const fluid::FluidMesh& fm, const std::vector<int>& unknown, const fluid::ClassifiedBoundary& bc,
                 const std::vector<int>& solid_node, const std::vector<char>& fixed,
                 const std::vector<Eigen::Vector3d>& x);
  /// Correction 1 on u (all solids' velocities, system dof order): masses per solid node, fixed
  /// dofs flagged. Adds what it removed to report.removed_kinetic.
  void project_start_velocity(Eigen::VectorXd& u, const Eigen::VectorXd& node_masses, const std::vector<char>& fixed,
                              ClosedVolumeReport& report) const;
  /// q̂ of each region (correction 2) from the TetMesh vertices moved by h ū, ū the projected
  /// start velocity (walls at rest).
  void predict_motion(const std::vector<Eigen::Vector3d>& x_predicted);
  /// w_c of region c on the m pressure unknowns (the unit dilatation, Σ_i w_i = 1).
  Eigen::VectorXd unit_source(int c, const fluid::FluidMesh& fm, const std::vector<int>& unknown, int m) const;
  /// V_c(x) − V₀_c per region [m³], TetMesh vertices at x.
  std::vector<double> excess(const std::vector<Eigen::Vector3d>& x) const;
  /// a_c = ∂V_c/∂x at the step's start (the solid dofs) [m²].
  const Eigen::VectorXd& gradient(int c) const { return gradient_[c]; }
  /// Correction 2: adds w_i S_c to r at the pressure unknowns of each region, for a step of length h.
  void add_volume_source(double h, const fluid::FluidMesh& fm, const std::vector<int>& unknown, Eigen::VectorXd& r,
                         ClosedVolumeReport& report) const;
  /// The regions of the last begin_step.
  const std::vector<ClosedRegion>& regions() const { return regions_; }
  /// (V(x) − V₀)/V₀ of the region where it is largest in size (0 without regions): x the TetMesh
  /// vertices of the last begin_step's mesh moved to the solids' new positions.
  double relative_error(const std::vector<Eigen::Vector3d>& x) const;
  /// Reference volumes by region key (checkpoints).
  const std::map<int, double>& reference_volumes() const { return reference_; }
  void set_reference_volumes(std::map<int, double> reference) { reference_ = std::move(reference); }

 private:
  std::map<int, double> reference_;            // key -> V₀ [m³]
  std::vector<ClosedRegion> regions_;
  std::vector<double> volume_;                 // V(xⁿ) per region [m³]
  std::vector<double> nonlinear_;              // q̂ per region [m³]
  std::vector<Eigen::VectorXd> gradient_;      // a per region [m²]
};

}  // namespace tetfsi::coupling
