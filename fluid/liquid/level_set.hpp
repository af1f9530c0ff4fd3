#pragma once
/// @file level_set.hpp
/// The liquid region as a nodal (P1) level set phi on the fluid mesh: liquid where phi < 0, air
/// where phi >= 0, |phi| the distance to the surface within a band (Osher & Sethian 1988; for
/// liquids, Foster & Fedkiw 2001). Each step the runner
///   1. advects phi semi-Lagrangian onto the new mesh (advect_nodal in semi_lagrangian.hpp),
///   2. redistances it: the nodes of cut tets keep their values (they alone place the surface, so
///      the liquid volume does not change), every other node gets the distance to the piecewise-
///      linear zero set (its marching-tets triangles) continued in their planes across the walls
///      it ends on, with the sign kept, clamped to +-band (the first time, at set_liquid, every
///      node gets the distance);
///   3. restores the volume: phi += delta with the one constant delta for which the liquid volume
///      sum_t |Omega_t| equals the target (the initial volume plus what sources added). A level
///      set alone loses volume where the surface curves (Enright et al. 2002); the global shift
///      is the simplest correction that keeps it exactly, at the price of moving the whole surface
///      by the (small) mean loss.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::fluid {

/// Signed distance from x to the axis-aligned box [lo, hi] (negative inside) [m].
double box_distance(const Eigen::Vector3d& x, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

/// Nodal level set from a signed distance function (negative inside the liquid) [m].
Eigen::VectorXd sample_level_set(const FluidMesh& mesh, const std::function<double(const Eigen::Vector3d&)>& sdf);

/// Liquid volume sum_t |Omega_t| of the level set phi [m^3] (exact for P1 phi).
double liquid_volume(const FluidMesh& mesh, const Eigen::VectorXd& phi);

/// The zero set of phi: one or two triangles per cut tet (marching tets), vertices where the
/// edges cross zero (shared between tets, one per cut edge, in order of first appearance),
/// oriented with normals along grad phi (out of the liquid). `vertex_edge` (if given) receives
/// the two nodes of the edge each vertex lies on (liquid node first).
mesh::SurfaceMesh zero_set(const FluidMesh& mesh, const Eigen::VectorXd& phi,
                           std::vector<std::array<int, 2>>* vertex_edge = nullptr);

/// The closed surface of the liquid for renderers: the zero set plus the wet parts of the fluid
/// mesh's boundary faces (walls, open faces, solid interfaces), sharing vertices, oriented outward.
/// `vertex_velocity` (if given) receives the node-averaged velocity at each vertex, interpolated
/// linearly along edges [m/s].
mesh::SurfaceMesh liquid_surface(const FluidMesh& mesh, const Eigen::VectorXd& phi, const TetVectors& velocity,
                                 std::vector<Eigen::Vector3d>* vertex_velocity = nullptr);

/// Sets to 0 the values within 1e-9 mean edge lengths of 0. A node on the surface reads 0 or
/// +-round-off depending on how phi was computed (a box region or the same box as a surface file;
/// a value interpolated back at the same point); since cut tets keep their values (redistance),
/// the round-off would otherwise decide for good which side such a node is on and leave slivers
/// of liquid of zero thickness. Moves the surface by at most that distance.
void snap_to_surface(const FluidMesh& mesh, Eigen::VectorXd& phi);

/// Makes liquid (phi = -DBL_MIN) every node at phi = 0 that has no air neighbour (phi > 0) and is
/// joined to a liquid node (phi < 0) directly or through such nodes: it lies on no free surface. A liquid region's face that lies on
/// a wall (a column standing on the floor: box_distance is 0 at the floor's nodes under it) or on
/// another region's face puts it there; left at 0 it counts as air, so it is a node of the surface
/// with p = 0, and the liquid above a floor of such nodes fell freely in the first step. Every tet
/// around such a node is full of liquid either way, so no surface moves and no volume changes.
void wet_enclosed_zeros(const FluidMesh& mesh, Eigen::VectorXd& phi);

/// Replaces phi by the signed distance to its zero set, clamped to [-band, band] (see file doc);
/// where the zero set ends on the mesh boundary (a wall, a solid), a triangle there also counts as
/// continued in its plane across that edge, taken no nearer than half its own distance. With
/// keep_cut_tets the nodes of tets that phi cuts keep their values, so the liquid volume is kept
/// exactly; without, a liquid against a wall that leans outward (in a bowl) lost 0.5% of its volume
/// per step at 2 cells deep (fluid/README.md). Nodes of a phi without zero set keep their sign at
/// distance band. The distance is exact in the inner half of the band and found by closest-triangle
/// propagation beyond (zero_set_distance.hpp: a few distance evaluations per node instead of a
/// search over every triangle within the band). @throws std::invalid_argument if band <= 0 or phi does not match the mesh
void redistance(const FluidMesh& mesh, Eigen::VectorXd& phi, double band, bool keep_cut_tets = false);

/// Adds the constant delta to phi for which liquid_volume equals `target` within
/// relative_tolerance (or the closest found in 60 secant-bisection steps); returns delta [m].
/// @throws std::invalid_argument if target < 0
double restore_volume(const FluidMesh& mesh, Eigen::VectorXd& phi, double target, double relative_tolerance = 1e-12);

}  // namespace tetfsi::fluid
