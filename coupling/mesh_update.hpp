#pragma once
/// @file mesh_update.hpp
/// How the shared fluid-solid mesh follows the solids from one coupled step to the next
/// (Chentanez et al. 2006, §3.1: "the fluid mesh is regenerated every time step so that it
/// conforms to the solid"; step 1 of CoupledStepper::step).
///
/// The solid tets are Lagrangian: they keep their connectivity and move with the displacement.
/// The fluid vertices follow by a stiffened Laplacian of the solid motion (mesh::move_with_solids:
/// box-boundary vertices fixed, small tets stiffer, so the fine tets next to a solid move almost
/// rigidly with it and the large tets farther away absorb the distortion). Then,
/// depending on the policy, the fluid is remeshed with CGAL (mesh::remesh_step) with the solid tets
/// and the interface frozen, so every solid vertex survives and solid state carries over through
/// `old_index`. The fluid's fields are moved onto the new mesh by the advection step
/// (fluid::FluidSolver::predict back-traces from the new mesh into the old one).
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mesh/mesh_motion.hpp"
#include "mesh/remesh_region.hpp"
#include "mesh/remesher.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::coupling {

enum class MeshUpdatePolicy {
  kMove,              ///< move the fluid vertices with the solids; never remesh
  kRemeshWhenNeeded,  ///< move; remesh when the moved fluid's min dihedral angle drops too low
  kRemeshEveryStep,   ///< move and remesh every step (the paper's choice)
};

/// "move" | "remesh_when_needed" | "remesh_every_step". @throws std::invalid_argument otherwise
MeshUpdatePolicy parse_mesh_update_policy(const std::string& name);
std::string to_string(MeshUpdatePolicy policy);

/// How MeshUpdater solves the stiffened Laplacian of the mesh motion on each mesh it moves.
enum class MotionSolver {
  kAuto,      ///< kCholesky up to MeshUpdateOptions::amg_motion_above_tets fluid tets, kAmg above
  kCholesky,  ///< factorized once per mesh (CHOLMOD), then two triangular solves per step
  kAmg,       ///< CG with a BoomerAMG V-cycle (set up once per mesh) from the extrapolated motion
};

/// "auto" | "cholesky" | "amg". @throws std::invalid_argument otherwise
MotionSolver parse_motion_solver(const std::string& name);

struct MeshUpdateOptions {
  MeshUpdatePolicy policy = MeshUpdatePolicy::kRemeshWhenNeeded;
  mesh::MeshMotionOptions motion;  ///< how the fluid vertices follow the solids
  /// The motion's solver. A factorization costs seconds once per mesh at a million fluid tets
  /// (2.1 s at 409k, 6.7-7.2 s at 962k on 2 cores) and is the largest item of the step's memory
  /// (190 MB at 409k fluid tets; at 962k about 640 MB, where the rest of the step's peak is 1.1 GB:
  /// it grows as the mesh's n^{4/3} under nested dissection), but then moves the
  /// mesh in about 0.07 s per step at 409k and 0.2 s at 962k (with the quality check); the AMG
  /// solve needs neither, at about 0.1 s per step at 409k and 0.31-0.46 s at 962k (5 iterations
  /// per component at 409k, MeshMotionOptions::step_reduction; docs/scaling.md).
  MotionSolver motion_solver = MotionSolver::kAuto;
  /// kAuto: the fluid tet count above which the motion is solved by AMG. Below it the factorization
  /// has paid for itself within 20-60 steps (99k, 409k fluid tets) and its memory is a modest part
  /// of the step's; above it the factor would be the step's largest item (about 60% more memory at
  /// 962k) for about 0.1 s per step less once its 7 s set-up has been paid.
  int amg_motion_above_tets = 500'000;
  /// kRemeshWhenNeeded: remesh when the moved fluid's minimum dihedral angle is below this [deg]
  /// (or below half the angle the step started from, whichever is smaller, so that a mesh that
  /// starts with a 7° sliver is not remeshed every step for it).
  double remesh_below_deg = 10.0;
  /// Remeshing options (target edge length, band, passes, sliver pass). In CoupledStepper a
  /// target_edge_length of 0 is replaced by the mean edge length of the fluid tets touching the
  /// solids at start, and a band of 0 by four times that. The
  /// policy sets remesh_only_when_needed, adaptive_band and min_dihedral_deg (the threshold).
  mesh::RemeshOptions remesh = [] {
    mesh::RemeshOptions o;
    o.target_edge_length = 0;
    return o;
  }();
};

struct MeshUpdateReport {
  bool remeshed = false;
  double min_dihedral_deg = 0;  ///< of the fluid tets after the update
  double seconds = 0;           ///< motion + quality check + remeshing
  double motion_seconds = 0;    ///< of which the stiffened-Laplacian motion
  int motion_iterations = 0;    ///< CG iterations of the motion, three components (MotionSolver::kAmg)
  double check_seconds = 0;     ///< of which the validity and angle check of the moved mesh
  int passes = 0;               ///< CGAL remeshing passes (0 when not remeshed)
  bool remesh_rejected = false; ///< remeshing was tried but did not beat the moved mesh's quality
  /// A refit (SizeFieldRequest) was asked for and the mesh now fits size_now: remeshed for it, or
  /// the field had not moved enough anywhere.
  bool size_field_fitted = false;
};

struct MeshUpdateResult {
  mesh::TetMesh mesh;
  /// The input mesh's vertices after the motion and before any remeshing, indexed like the input
  /// mesh: every solid vertex v at solid_positions[v], the fluid vertices where the stiffened
  /// Laplacian put them. Equal to mesh.vertices when the mesh was only moved. The fields a fluid
  /// solver computed on the input mesh are drawn on these positions (CoupledStepper::
  /// fluid_node_positions), so that a frame shows fluid and solids at the same time.
  std::vector<Eigen::Vector3d> moved_vertices;
  /// For each vertex of `mesh`, its index in the input mesh (-1 for a vertex the remesher made).
  /// The identity when the mesh was only moved.
  std::vector<int> old_index;
  MeshUpdateReport report;
};

/// A sizing field for one mesh update (e.g. finer at a liquid's free surface).
struct SizeFieldRequest {
  /// CGAL's sizing in every remesh of the update: min(target_edge_length, size_at). Empty: none.
  mesh::SizeField size_at;
  /// Refit (both set): the update also remeshes, whatever the policy, the fluid tets where the
  /// field moved from size_then to size_now by more than `ratio` (mesh::resized_tets, `rings`
  /// rings around them), with far_edge as the target there, together with the band around the
  /// solids if the policy remeshes this step; the result is kept unless it has a flat or inverted
  /// tet or a fluid dihedral angle below both the threshold and the moved mesh's.
  mesh::SizeField size_then, size_now;
  double far_edge = 0;
  double ratio = 1.3;
  int rings = 2;
};

/// Mean edge length [m] of the fluid tets with a vertex on a solid: the remeshing target that
/// keeps a mesh graded toward the solids as fine near them as it started.
double fluid_edge_length_near_solids(const mesh::TetMesh& mesh);

/// Step by step mesh update. The fluid vertices follow the solids by the stiffened Laplacian
/// measured from the mesh as it was after the last remesh (mesh::MeshMotion: assembled once,
/// warm-started CG each step), then the fluid is remeshed according to `options.policy`.
class MeshUpdater {
 public:
  explicit MeshUpdater(MeshUpdateOptions options);
  ~MeshUpdater();
  const MeshUpdateOptions& options() const { return options_; }
  MeshUpdateOptions& options() { return options_; }

  /// @param mesh  the mesh this updater returned last time (or the initial mesh)
  /// Other parameters and the result as update_mesh below.
  MeshUpdateResult update(const mesh::TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                          double start_min_dihedral_deg);

  /// Sizing for the next update (SizeFieldRequest).
  void set_size_field(SizeFieldRequest request) { size_request_ = std::move(request); }

  /// Checkpoints (coupled_stepper_state.cpp): the cached motion's reference positions and state.
  /// read_state rebuilds it on `mesh` (the mesh update() returned last) at those positions.
  void write_state(BinaryWriter& out) const;
  void read_state(BinaryReader& in, const mesh::TetMesh& mesh);

 private:
  /// The motion of `reference` (moved every step until the next remesh), solved by
  /// options_.motion_solver.
  std::unique_ptr<mesh::MeshMotion> make_motion(const mesh::TetMesh& reference) const;
  MeshUpdateOptions options_;
  SizeFieldRequest size_request_;  ///< for the next update only
  std::unique_ptr<mesh::MeshMotion> motion_;
};

/// One update without a cached motion (a MeshUpdater used once).
/// Moves `mesh` so that every solid vertex v lands on `solid_positions[v]`, then remeshes the fluid
/// according to `options.policy`.
/// @param mesh             the shared mesh at the previous step (positively oriented tets)
/// @param solid_positions  new position of every vertex (read only for vertices of solid tets) [m]
/// @param start_min_dihedral_deg  the fluid's minimum dihedral angle before this update [deg]
/// @throws mesh::MeshError if the motion inverts or flattens a tet (the step is too large for the
///         mesh). A remeshed fluid is used only if its minimum dihedral angle beats the moved one.
MeshUpdateResult update_mesh(const mesh::TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                             const MeshUpdateOptions& options, double start_min_dihedral_deg);

}  // namespace tetfsi::coupling
