#pragma once
/// @file viscous_boundary.hpp
/// Which fluid nodes the viscous step holds at a prescribed velocity (Dirichlet), from the
/// classified boundary of this step:
///  - no-slip walls: u = 0, or the patch velocity of a moving wall (BoundaryPatch of kind kWall
///    with a tangential `velocity`: the lid of a driven cavity, the moving plate of Couette flow;
///    only the patch's faces whose normal lies along its region's thinnest extent, not the faces of
///    the walls it meets whose centroids fall inside the region along its rim);
///  - solid interfaces (no-slip): u = the solid's vertex velocity (BoundaryConditions::
///    solid_vertex_velocity, else BoundaryConditions::no_slip_velocity; 0 if both are empty);
///  - inflow patches: u = the patch velocity (its profile, if any) — the full vector, tangential
///    part included, which the inviscid projection cannot impose;
///  - open faces (p = 0), slip walls and solids, and wall patches marked `slip` (symmetry planes):
///    natural, zero viscous traction (the projection still imposes u.n there).
/// A node on faces of several kinds takes the first of: interface, inflow, moving wall, wall
/// (Dirichlet wins over natural: the rim of an open outlet in a no-slip pipe is held at rest).
#include <Eigen/Core>
#include <vector>

#include "fluid/boundary/boundary_conditions.hpp"
#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::fluid {

/// The tangential condition of walls and solids for the viscous step.
enum class WallCondition { kNoSlip, kSlip };

/// Parses "no_slip" / "slip". @throws std::invalid_argument otherwise.
WallCondition parse_wall_condition(const std::string& name);

/// Dirichlet data of the viscous step, per fluid node.
struct ViscousNodes {
  std::vector<char> fixed;                ///< 1: velocity prescribed at this node
  std::vector<Eigen::Vector3d> velocity;  ///< the prescribed velocity where fixed [m/s], else 0
};

/// The Dirichlet nodes of `mesh` under this step's classified boundary `cb` and conditions `bc`
/// (moving-wall velocities, inflow profiles and solid velocities are read from `bc`); moving walls
/// and inflows are Dirichlet under either wall condition.
ViscousNodes viscous_nodes(const FluidMesh& mesh, const ClassifiedBoundary& cb, const BoundaryConditions& bc,
                           WallCondition walls);

}  // namespace tetfsi::fluid
