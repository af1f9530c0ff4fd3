#pragma once
/// @file fluid_mesh.hpp
/// The fluid part of a TetMesh with the per-tet geometry the P1 operators need.
///
/// Discretization (Ando, Thuerey, Wojtan 2013, "Highly adaptive liquid simulations on
/// tetrahedral meshes", sec. 3): pressure p lives at the mesh NODES (P1 hat functions phi_i),
/// velocity u_t is constant per TET. The pressure matrix L = G^T V G (the P1 stiffness matrix)
/// is symmetric positive semi-definite on every mesh with positive tet volumes, Delaunay or not
/// (circumcentric pressures as in Klingner, Feldman, Chentanez & O'Brien 2006 need a Delaunay mesh
/// for positive weights).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::fluid {

/// A triangle on the boundary of the fluid region, seen from its one fluid tet.
struct BoundaryFace {
  int tet = -1;                  ///< fluid tet owning the face
  int local_face = -1;           ///< face opposite local vertex `local_face` of that tet
  std::array<int, 3> nodes{};    ///< fluid node indices of the triangle
  Eigen::Vector3d normal;        ///< unit normal pointing OUT of the fluid
  double area = 0.0;             ///< [m^2]
  int other_subdomain = 0;       ///< subdomain label of the tet across (a solid), 0 = outer boundary
};

/// The gradients ∇φ_k of the four hat functions of every tet [1/m]: ∇φ₁, ∇φ₂, ∇φ₃ are the rows
/// of the inverse of the edge matrix [x₁ − x₀, x₂ − x₀, x₃ − x₀] and are stored; ∇φ₀ = −(∇φ₁ + ∇φ₂ +
/// ∇φ₃) (the hat functions sum to one) is computed when read, the same sum, so it has the same bits
/// as a stored one would (72 instead of 96 bytes per tet). Read as grad[t][k].
struct HatGradients {
  std::vector<std::array<Eigen::Vector3d, 3>> stored;  ///< #T: ∇φ₁, ∇φ₂, ∇φ₃

  /// The four gradients of one tet, by value.
  struct OfTet {
    const std::array<Eigen::Vector3d, 3>& g;
    Eigen::Vector3d operator[](int k) const { return k == 0 ? Eigen::Vector3d(-(g[0] + g[1] + g[2])) : g[k - 1]; }
  };
  OfTet operator[](int t) const { return {stored[t]}; }
};

/// Fluid tets (subdomain kFluidSubdomain) of a TetMesh, renumbered compactly.
struct FluidMesh {
  std::vector<Eigen::Vector3d> nodes;                 ///< #N node positions [m]
  std::vector<int> node_to_mesh_vertex;               ///< #N fluid node -> TetMesh vertex
  std::vector<int> mesh_vertex_to_node;               ///< #V TetMesh vertex -> fluid node or -1
  std::vector<std::array<int, 4>> tets;               ///< #T fluid node indices, positively oriented
  std::vector<int> tet_to_mesh_tet;                   ///< #T fluid tet -> TetMesh tet
  std::vector<double> volume;                         ///< #T tet volumes V_t [m^3]
  HatGradients grad;                                  ///< #T gradients of the 4 hat functions [1/m], grad[t][k]
  std::vector<std::array<int, 4>> neighbor;           ///< fluid tet across the face opposite vertex k, -1 if none
  std::vector<BoundaryFace> boundary_faces;           ///< every fluid boundary triangle
  std::vector<double> dual_volume;                    ///< #N lumped node volume sum_t V_t / 4 [m^3]
  std::vector<std::vector<int>> node_tets;            ///< #N fluid tets around each node (ascending)

  int num_nodes() const { return static_cast<int>(nodes.size()); }
  int num_tets() const { return static_cast<int>(tets.size()); }
  /// Centroid of fluid tet t [m], (x₀ + x₁ + x₂ + x₃)/4 from its nodes (centroid_at; not stored:
  /// 24 bytes per tet, and the walks that read it read the nodes' neighbourhood anyway).
  Eigen::Vector3d centroid(int t) const;
  /// Mean edge length over all fluid tets [m].
  double mean_edge_length() const;
};

/// Builds the fluid mesh from the tets labelled kFluidSubdomain (all tets if `subdomain` is empty).
/// The fluid tets are numbered along a Morton (Z-order) curve through their centroids and the
/// nodes in the order the tets first touch them, so that neighbours sit close in memory (the
/// step's point location, interpolation and assembly read mostly cached data; the mesher's own
/// order scatters them). Runs in O(T log T) (faces matched by sorting; deterministic).
/// @throws std::invalid_argument if there is no fluid tet, a vertex index is out of range, or a
///         fluid tet has non-positive volume (the message names the tet)
FluidMesh build_fluid_mesh(const mesh::TetMesh& mesh);

/// Re-reads the node positions of `fm` from `mesh` and recomputes its geometry (volumes,
/// gradients, centroids, boundary normals and areas, dual volumes), keeping its topology and
/// numbering: for a mesh whose tets and subdomain labels are those `fm` was built from (a moved,
/// not remeshed, mesh), each tet, node and face gets bit for bit what build_fluid_mesh(mesh) gives
/// it (which may number them otherwise; dual volumes to round-off), without matching faces.
/// @throws std::invalid_argument if a fluid tet has non-positive volume (the message names it)
void update_fluid_mesh_geometry(const mesh::TetMesh& mesh, FluidMesh& fm);

/// The same with the node positions given directly (one per node of fm) [m].
void update_fluid_mesh_geometry(std::vector<Eigen::Vector3d> nodes, FluidMesh& fm);

/// The positions in `mesh` (fm's TetMesh moved) of fm's nodes, in fm's node order [m].
std::vector<Eigen::Vector3d> moved_nodes(const mesh::TetMesh& mesh, const FluidMesh& fm);

/// The centroid of tet t of fm with its nodes at `nodes`, bit for bit as FluidMesh::centroid
/// computes it from fm.nodes [m].
inline Eigen::Vector3d centroid_at(const FluidMesh& fm, const std::vector<Eigen::Vector3d>& nodes, int t) {
  const auto& v = fm.tets[t];
  return 0.25 * (nodes[v[0]] + nodes[v[1]] + nodes[v[2]] + nodes[v[3]]);
}

inline Eigen::Vector3d FluidMesh::centroid(int t) const { return centroid_at(*this, nodes, t); }

/// For each tet of `to`, the tet of `from` built from the same TetMesh tet with the same TetMesh
/// vertices: two fluid meshes of one topology (a moved mesh, or jittered copies of one mesh) whose
/// numberings may differ, since build_fluid_mesh numbers along the centroids' curve. Empty if `to`
/// has a tet that `from` lacks (a remeshed mesh). O(T); the identity when the numberings agree.
std::vector<int> matching_tets(const FluidMesh& from, const FluidMesh& to);

}  // namespace tetfsi::fluid
