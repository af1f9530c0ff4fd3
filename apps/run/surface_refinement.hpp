#pragma once
/// @file surface_refinement.hpp
/// A fluid mesh finer at a liquid's free surface (`fluid.surface_edge_length`, fluid and coupled
/// runners; fluid/README.md, "Adaptive mesh"). The target edge length at distance d from the
/// surface is
///
///   h(d) = h_s + (h_far - h_s) clamp((d - 3 h_s) / G, 0, 1),   G = max(grading_distance, 3 h_s),
///
/// h_s = surface_edge_length, h_far = mesh.edge_length, d = |phi| (the level set's distance).
/// The first mesh uses h at the distance to the initial liquid. When a node within 1.5 h_s of the
/// surface lay outside the refined zone (nodes within 3 h_s) at the last fit, the fluid is
/// remeshed for h where h moved since that fit (mesh::resized_tets: by more than kResize, with
/// kRings rings of tets around them), and the fit is recorded again (mark).
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "apps/scene/scene.hpp"
#include "fluid/fluid_solver.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/tet_mesh.hpp"

namespace tetfsi::run {

class SurfaceRefinement {
 public:
  /// h moved at a vertex by more than this factor since the last fit: its tets are remeshed
  /// (CGAL's isotropic remeshing keeps edges within [4/5, 4/3] of its target, Botsch & Kobbelt
  /// 2004, so a smaller change would hardly change the mesh).
  static constexpr double kResize = 1.3;
  /// Rings of tets around the misfit ones that are remeshed with them (room to grade).
  static constexpr int kRings = 2;

  SurfaceRefinement() = default;  ///< off
  /// @param surface_edge h_s [m] (> 0), @param far_edge h_far [m], @param grading_distance [m]
  SurfaceRefinement(double surface_edge, double far_edge, double grading_distance);

  bool on() const { return law_.surface_edge > 0; }
  double surface_edge() const { return law_.surface_edge; }
  double far_edge() const { return law_.far_edge; }
  /// h(d) above [m].
  double size(double d) const { return law_(d); }
  /// h at the distance |distance(x)| (e.g. to the initial liquid regions).
  std::function<double(const Eigen::Vector3d&)> field(std::function<double(const Eigen::Vector3d&)> distance) const;
  /// h at the solver's level set, interpolated on its mesh, both as they are at the field's first
  /// call (copied then with a point locator, so an unused field costs nothing). Call from one
  /// thread; the solver must outlive the field.
  std::function<double(const Eigen::Vector3d&)> current_field(const fluid::FluidSolver& solver) const;
  /// Records the fit: the refined zone of the solver's level set and h as it is now (a copy of its
  /// mesh and level set), after a remesh for h or when h was found not to have moved enough.
  void mark(const fluid::FluidSolver& solver);
  /// h at the last mark (empty before the first).
  const std::function<double(const Eigen::Vector3d&)>& fitted_field() const { return fitted_; }
  /// The fluid tets of `mesh` where h moved from the last mark to `size_now` (current_field) by
  /// more than kResize, with kRings rings around them (mesh::resized_tets); empty if none.
  std::vector<char> resized_tets(const mesh::TetMesh& mesh,
                                 const std::function<double(const Eigen::Vector3d&)>& size_now) const;
  /// True when a node within 1.5 h_s of the surface of `phi` was outside the refined zone at the
  /// last mark (or the node count changed since).
  bool left_zone(const Eigen::VectorXd& phi) const;
  /// One line for run.log.
  std::string summary() const;

 private:
  /// h(d) (the fields copy it, so they do not depend on this object's address).
  struct SizeLaw {
    double surface_edge = 0, far_edge = 0, grading = 0;
    double operator()(double d) const;
  } law_;
  std::vector<char> refined_node_;  ///< per fluid node: |phi| < 3 h_s at the last mark
  std::function<double(const Eigen::Vector3d&)> fitted_;  ///< h at the last mark
};

/// The refinement a resolved scene asks for: on for a liquid with `fluid.fill` "regions" and
/// `fluid.surface_edge_length` > 0 (h_far = mesh.edge_length, G from mesh.grading_distance).
SurfaceRefinement surface_refinement(const scene::Json& scene);

/// The first mesh's grading toward the solids, on the mesh as it is now:
///   h(x) = h_near + (h_far - h_near) min(1, d(x) / grading_distance),
/// d the distance to the solids' surfaces (the interface triangles of `mesh`; the same formula as
/// the Mesh_3 sizing field of mesh::build_complex), for a remesh that reaches the solids with a
/// target of h_far. Empty if `sizing` has no grading (no edge_length_near_solids below
/// edge_length, or no grading_distance) or `mesh` no interface. Call from one thread.
std::function<double(const Eigen::Vector3d&)> solid_graded_field(const mesh::TetMesh& mesh,
                                                                 const mesh::MeshSizing& sizing);

}  // namespace tetfsi::run
