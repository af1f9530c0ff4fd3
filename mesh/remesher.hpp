#pragma once
/// @file remesher.hpp
/// Per-step remeshing of the fluid around moving solids (issue 5, part 1).
///
/// One step: (1) the solid vertices move to their new positions; (2) the fluid vertices follow by
/// a stiffened Laplacian of the solid displacement (mesh_motion.hpp; box-boundary vertices
/// fixed), so that nearby fluid tets are carried along instead of inverted; (3) the fluid alone is
/// remeshed with CGAL tetrahedral_isotropic_remeshing while the solid tets are hidden as
/// subdomain 0 and restored after, so the interface triangles and the solid tets are kept
/// identically; (4) the fluid's minimum dihedral
/// angle is checked, and the remesh is repeated with more iterations (and a larger band, then the
/// whole fluid) if it is below the threshold. With a band only the band, a ring of tets around it
/// and the solids are handed to CGAL, so the cost follows the band, not the box. Optionally
/// (remesh_only_when_needed) step (3) is skipped while the moved mesh is still good.
#include <string>
#include <functional>
#include <vector>

#include "mesh/mesh_motion.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

struct RemeshOptions {
  /// Fluid edge length [m]. Use the mesh's own mean fluid edge length (mean_edge_length in
  /// quality.hpp), not Mesh_3's size bound h: for a 104k-tet sphere-in-box complex meshed with
  /// h = 0.042 (mean edge 0.056) a target of h gave 232k tets, 70 s and a second pass, the mean edge
  /// 106k tets, 8.4 s, min dihedral 16 deg. Remeshing a graded mesh uniformly to its fine size left
  /// 0.1 deg slivers at the protected interface.
  double target_edge_length = 0.1;
  /// A further target [m] at each point (finer near a liquid's surface): CGAL's sizing field is
  /// the smaller of this and target_edge_length. Empty: uniform.
  std::function<double(const Eigen::Vector3d&)> size_at;
  int iterations = 2;               ///< CGAL remeshing iterations of the first pass
  /// Passes before giving up: each further pass has one more iteration and, with a band, twice
  /// the band; the third and later passes remesh the whole fluid.
  int max_passes = 2;
  double min_dihedral_deg = 5.0;    ///< accept the fluid mesh when its min dihedral angle is above
  double band = 0.0;                ///< > 0: remesh only fluid tets within this distance [m] of a
                                    ///< solid vertex (others hidden like the solid); 0: all fluid
  /// Per tet (non-empty): remesh exactly the fluid tets flagged here (band and seeds are not used;
  /// the region CGAL gets is built around them as for a band), e.g. where a liquid surface's
  /// sizing field no longer matches the mesh. Passes after the first remesh the whole fluid.
  std::vector<char> remesh_tets;
  /// Move, remesh when needed: when true and the moved mesh is still good (no flat or inverted
  /// tet, fluid min dihedral >= min_dihedral_deg, and no fluid tet's volume changed by more than a
  /// factor max_volume_ratio), the moved mesh is returned as is (RemeshReport::remeshed false,
  /// old_index the identity). False: remesh every step.
  bool remesh_only_when_needed = false;
  double max_volume_ratio = 2.0;    ///< see remesh_only_when_needed
  /// With remesh_only_when_needed and band > 0: the band is measured from the vertices of the
  /// fluid tets that failed the check (below min_dihedral_deg, or volume changed by more than
  /// max_volume_ratio) instead of from every solid vertex, so only where the motion spoiled the
  /// mesh is remeshed.
  bool adaptive_band = false;
  /// After each CGAL pass, free fluid vertices of tets with a dihedral angle below this [deg] are
  /// moved to open them (sliver_perturbation.hpp); 0: no sliver pass.
  double sliver_pass_below_deg = 10.0;
  /// How the fluid vertices follow the solids before remeshing (stiffened Laplacian).
  MeshMotionOptions motion;
};

struct RemeshReport {
  int num_tets = 0;
  int num_fluid_tets = 0;
  double min_dihedral_deg = 0.0;  ///< over the fluid tets after remeshing
  double max_dihedral_deg = 0.0;
  int passes = 0;                 ///< remeshing passes run (1 unless the quality check failed)
  bool quality_ok = false;        ///< min_dihedral_deg >= options.min_dihedral_deg
  double seconds = 0.0;           ///< wall time of the whole step
  bool remeshed = true;           ///< false: the moved mesh was good enough (remesh_only_when_needed)
  bool local = false;             ///< CGAL got only the band's regions (+ a ring and the solids), not the mesh
  int remeshed_fluid_tets = 0;    ///< fluid tets handed to CGAL for remeshing (last pass)
  int region_tets = 0;            ///< tets in CGAL's triangulations (band, ring, solids; last pass)
  int slivers_before = 0, slivers_after = 0;  ///< fluid tets below sliver_pass_below_deg around the pass (last pass)
  /// Wall time [s] of the phases: mesh motion + its inversion check, building CGAL's triangulations
  /// from the arrays (with finding their regions, band_regions), CGAL's remeshing, copying back,
  /// the sliver pass (all passes summed), checks.
  double motion_seconds = 0.0, build_seconds = 0.0, cgal_seconds = 0.0, copy_seconds = 0.0, sliver_seconds = 0.0,
         check_seconds = 0.0;
  std::string summary() const;
};

struct RemeshResult {
  TetMesh mesh;
  /// For each vertex of `mesh`, its index in the input mesh, or -1 for a vertex the remesher made.
  /// Solid vertices are always kept, so solid state (velocities, ...) carries over through this.
  std::vector<int> old_index;
  RemeshReport report;
};

/// Remeshes the fluid tets (label kFluidSubdomain) of `mesh` (CGAL; solid tets and the interface
/// kept). @pre every tet positively oriented, the mesh fills a convex box
/// `seeds` (per vertex, optional): the band is measured from these vertices instead of the solid
/// vertices (RemeshOptions::adaptive_band).
RemeshResult remesh_fluid(const TetMesh& mesh, const RemeshOptions& options, int iterations,
                          const std::vector<char>& seeds = {});

/// One full step: move (move_with_solids, mesh_motion.hpp), check that no tet inverted, remesh the fluid with
/// the quality check and extra passes.
/// @throws MeshError if the motion inverts tets (step too large for the mesh)
RemeshResult remesh_step(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                         const RemeshOptions& options);

}  // namespace tetfsi::mesh
