#pragma once
/// @file quality.hpp
/// Quality report of a tetrahedral mesh (no CGAL): tet counts per subdomain, dihedral angles,
/// radius-edge ratio, inverted and degenerate tets.
#include <array>
#include <map>
#include <string>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

/// The six dihedral angles [deg] of tet (a, b, c, d), one per edge, in the edge order
/// (ab, ac, ad, bc, bd, cd). The angle at edge ij is pi minus the angle between the outward
/// normals of the two faces that share it: theta = acos(-n1 . n2).
std::array<double, 6> dihedral_angles_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, const Eigen::Vector3d& d);

/// Radius-edge ratio R / l_min (circumradius over shortest edge); sqrt(6)/4 = 0.612 for the
/// regular tet, infinite for a flat one (CGAL Mesh_3's cell_radius_edge_ratio criterion).
double radius_edge_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& d);

/// Relative volume 6 V / l_max^3 of tet (a, b, c, d) (l_max its longest edge): 1/sqrt(2) for the
/// regular tet, <= 0 when inverted. |value| <= 6e-12 counts as degenerate (QualityReport).
double relative_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       const Eigen::Vector3d& d);

/// True if the tet is inverted or degenerate in the sense of QualityReport.
inline bool flat_or_inverted(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                             const Eigen::Vector3d& d) {
  return relative_volume(a, b, c, d) <= 6e-12;
}

struct QualityReport {
  std::map<int, int> tets_per_subdomain;  ///< label -> number of tets (label 1 if mesh has no labels)
  int num_vertices = 0;
  int num_tets = 0;
  double min_dihedral_deg = 0.0;   ///< over tets with positive volume
  double max_dihedral_deg = 0.0;
  double max_radius_edge = 0.0;
  int inverted = 0;    ///< signed volume < 0
  int degenerate = 0;  ///< |signed volume| <= 1e-12 * (longest edge)^3, counted apart from inverted

  /// One line for logs, e.g. "5012 tets (1: 4000, 2: 1012), dihedral [12.3, 160.1] deg, ...".
  std::string summary() const;
};

/// What a moving mesh needs checked each step, and no more: the minimum dihedral angle of the
/// tets with one label and how many of them are flat or inverted (quality_report also computes
/// every angle's acos, the radius-edge ratios and the per-label counts).
struct AngleCheck {
  double min_dihedral_deg = 0.0;  ///< over the tets with positive volume (0 if there are none) [deg]
  int flat_or_inverted = 0;       ///< tets with relative_volume <= 6e-12 (inverted or degenerate)
};

/// The minimum dihedral angle of a tet is acos of the largest cosine −n_i·n_j over its six edges
/// (n_i, n_j the outward unit normals of the two faces that meet there), so the check compares
/// cosines and takes one acos at the end. The result equals quality_report(mesh, subdomain)'s
/// min_dihedral_deg and inverted + degenerate exactly (the same cosines); parallel over tets
/// (TBB), independent of the thread count.
AngleCheck min_dihedral_check(const TetMesh& mesh, int subdomain);

/// Mean length [m] of the tet edges of the given subdomain (each edge counted once per tet that
/// has it). The natural remeshing target (RemeshOptions::target_edge_length).
double mean_edge_length(const TetMesh& mesh, int subdomain);

/// Quality of every tet of `mesh` (all tets, every subdomain).
QualityReport quality_report(const TetMesh& mesh);

/// Quality of the tets with the given label only (counts and angles restricted to them).
QualityReport quality_report(const TetMesh& mesh, int subdomain);

}  // namespace tetfsi::mesh
