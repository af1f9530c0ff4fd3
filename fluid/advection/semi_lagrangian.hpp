#pragma once
/// @file semi_lagrangian.hpp
/// Semi-Lagrangian advection from an OLD mesh to a NEW mesh (which may differ: remeshed, jittered).
///
/// Samples: every quantity (velocity, smoke density, temperature) is stored per tet and sampled at
/// the new tet centroids, so ONE back-trace per new tet serves all three.
/// Reconstruction on the old mesh: tet values are averaged to nodes with volume weights and
/// interpolated linearly (barycentric) inside tets; the back-trace always uses this continuous
/// velocity. Read at the foot as is (kSemiLagrangian) this averaging is a low-pass filter applied
/// EVERY step, about 0.29 dx^2 u'' per step, so the kinetic-energy loss per second grows as h shrinks.
/// Measured on inviscid Taylor-Green cells (test_fluid_taylor_green, dx = pi/16, h = 0.05 s, loss of
/// energy per second): semi-Lagrangian 36%, BFECC 7%, tet-linear (default) below 1%.
/// Back-trace: explicit midpoint rule (RK2), x_mid = x - h/2 u(x), x_back = x - h u(x_mid),
/// second order in time. Clamping: when x_mid or x_back lies outside the old fluid (outside the box,
/// inside a solid) the trace is cut back by bisection along the segment from x to the last point
/// inside the fluid (12 halvings). A sample centroid not inside the old fluid at all (a solid moved
/// away from it) takes the old values at the nearest tet the walk reached (clamped barycentric).
/// Backflow: with `exits` (boundary_conditions.hpp), a trace cut at an open face reads the normal part
/// (u.n) n of the clamped velocity where u.n < 0, the fluid entering there (ExitRule::kOpen). The exit
/// face is the boundary face of the clamped foot's tet with the smallest barycentric coordinate (the
/// foot lies within 2^-12 of the trace from it); if that coordinate exceeds 0.01 (the trace left
/// through an edge of a neighbouring tet) the clamped value is kept. A trace cut at the face of an inflow
/// with a velocity profile reads the prescribed velocity there (ExitRule::kInflow). Walls, solid
/// interfaces and uniform inflows keep the clamped value, so domains without open faces or profiled inflows advect exactly as without
/// `exits`.
#include <Eigen/Core>
#include <vector>

#include "fluid/advection/point_locator.hpp"
#include "fluid/boundary/boundary_conditions.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"

namespace tetfsi::fluid {

/// Per-tet fields carried by the fluid.
struct FluidFields {
  TetVectors velocity;           ///< [m/s]
  Eigen::VectorXd smoke;         ///< density of smoke [-]
  Eigen::VectorXd temperature;   ///< [K]
};

/// kSemiLagrangian: one back-trace and interpolation (first order in space, dissipative).
/// kBfecc: back and forth error compensation and correction (Kim, Liu, Llamas, Rossignac 2005;
///   Selle et al. 2008 for the limiter): f^ = A(f) (old -> new), f~ = A^R(f^) (new -> old, tracing
///   forward through the same old velocity), f_new = A(f + (f - f~)/2), reverting to f^ where the
///   result leaves [min, max] of the old nodal values around the foot. Cancels the leading
///   smoothing error of A (node averaging + interpolation); costs about 2.5 plain advections.
/// kLinear: semi-Lagrangian with a tet-wise linear reconstruction that keeps each tet's own value at
///   its centroid, f(x) = f_t + sum_k (lambda_k(x) - 1/4) f_nodes_k  (the gradient of the node
///   average, anchored at the tet value; limited to the range of f_t and the 4 node values). Unlike
///   the continuous interpolant it is the identity for a zero displacement on the same mesh, so it
///   does not smooth the field every step (its smoothing scales with the displacement, not with 1/h).
enum class AdvectionScheme { kSemiLagrangian, kBfecc, kLinear };

struct AdvectionReport {
  int clamped = 0;          ///< traces cut at the fluid boundary
  int outside_start = 0;    ///< new samples not inside the old fluid
  int backflow_feet = 0;    ///< samples whose tangential velocity was dropped at an open face (ExitRule::kOpen)
  int inflow_feet = 0;      ///< samples that took an inflow patch's velocity (ExitRule::kInflow)
};

/// Advects `old_fields` (on `old_mesh`) to the tets of `new_mesh` over h [s].
/// Deterministic: samples are processed in fixed blocks. Each walk starts at tet t of the old mesh
/// when both meshes have the same tets (the mesh only moved), else at the previous sample's tet in
/// the block (new-mesh order is spatially coherent) or from the grid.
/// `exits`: boundary_exits(old_mesh, bc) (one entry per old_mesh.boundary_faces), or nullptr to clamp
/// at every boundary face.
/// `node_weight`: per old tet, its weight in the node averages (nullptr: its volume). A liquid
/// passes its liquid volumes (fluid_solver.cpp), so that a tet holding a sliver of liquid, whose
/// velocity the projection barely constrains, hardly enters the reconstruction; and kLinear
/// anchors a foot at its tet's own value only where that tet's weight is its whole volume (a tet
/// full of liquid), reading the node interpolant elsewhere.
/// `old_locator`: a PointLocator of old_mesh to use (nullptr: one is built).
FluidFields advect(const FluidMesh& old_mesh, const FluidFields& old_fields, const FluidMesh& new_mesh, double h,
                   AdvectionReport* report = nullptr, AdvectionScheme scheme = AdvectionScheme::kSemiLagrangian,
                   const BoundaryExits* exits = nullptr, const std::vector<double>* node_weight = nullptr,
                   const PointLocator* old_locator = nullptr);

/// advect() onto old_mesh's tets with its nodes moved to `moved_nodes` (one per node; moved_nodes()
/// of fluid_mesh.hpp reads them from the moved TetMesh): the new fluid mesh need not exist, its
/// tets' centroids are computed from the nodes as it would compute them (centroid_at), so a caller
/// can move old_mesh in place afterwards (FluidSolver::predict keeps one fluid mesh instead of
/// two). Sample t's walk starts at old tet t. Bit for bit advect() onto the moved fluid mesh.
/// @throws std::invalid_argument for kBfecc (its reverse step reads the new mesh) or a node count
///         mismatch
FluidFields advect_onto_moved(const FluidMesh& old_mesh, const FluidFields& old_fields,
                              const std::vector<Eigen::Vector3d>& moved_nodes, double h,
                              AdvectionReport* report = nullptr,
                              AdvectionScheme scheme = AdvectionScheme::kSemiLagrangian,
                              const BoundaryExits* exits = nullptr, const std::vector<double>* node_weight = nullptr,
                              const PointLocator* old_locator = nullptr);

/// Advects a nodal (P1) field such as the level set of a liquid (liquid/level_set.hpp) from
/// `old_mesh` to the nodes of `new_mesh` over h [s]: each new node is traced back (RK2) through
/// the node-averaged `old_velocity` and reads the old field by linear interpolation at its foot.
/// Unlike advect(), a midpoint or foot outside the old fluid is clamped to the boundary tet the
/// walk ended in (clamped barycentric coordinates), not cut back along the trace: nodes lie on
/// the walls, and cutting would stop a wall node whose velocity points outward at all.
/// Deterministic.
/// `node_weight` and `old_locator` as for advect().
Eigen::VectorXd advect_nodal(const FluidMesh& old_mesh, const TetVectors& old_velocity,
                             const Eigen::VectorXd& old_values, const FluidMesh& new_mesh, double h,
                             AdvectionReport* report = nullptr, const std::vector<double>* node_weight = nullptr,
                             const PointLocator* old_locator = nullptr);

/// advect_nodal with back-and-forth error compensation (BFECC; Dupont & Liu 2003, with the
/// limiter of Selle et al. 2008): phi_hat = A(phi) as advect_nodal; phi_check = the old nodes traced
/// forward through the same velocity, reading phi_hat on the new mesh; the result is
///   A(phi + (phi - phi_check) / 2),
/// second order in space and time where smooth, and replaced by phi_hat at nodes where it leaves
/// the range of phi at its foot tet's nodes. Costs a second trace and a PointLocator of new_mesh.
/// It keeps thin sheets and drops that first-order interpolation flattens (the liquid's level
/// set; measured in fluid/README.md). Arguments and determinism as advect_nodal.
Eigen::VectorXd advect_nodal_bfecc(const FluidMesh& old_mesh, const TetVectors& old_velocity,
                                   const Eigen::VectorXd& old_values, const FluidMesh& new_mesh, double h,
                                   AdvectionReport* report = nullptr, const std::vector<double>* node_weight = nullptr,
                                   const PointLocator* old_locator = nullptr);

}  // namespace tetfsi::fluid
