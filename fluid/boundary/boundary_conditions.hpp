#pragma once
/// @file boundary_conditions.hpp
/// What happens on each boundary triangle of the fluid, and which nodes carry which condition.
///
///  - wall:      no flux, u.n = 0. Natural in the weak form: nothing to add (boundary_flux.hpp).
///  - inflow:    prescribed velocity u_in on a patch: adds int phi_i (u_in.n) dA to the divergence;
///               the tets touching the patch also receive the patch's smoke and temperature.
///  - open:      p = 0 (Dirichlet) at every node of the face; flow leaves or enters freely; fluid
///               entering (backflow) carries only its normal velocity (ExitRule::kOpen).
///  - interface: a face shared with a solid tet (TetMesh label >= 2); the solid's P1 vertex
///               velocities prescribe u.n (kinematic solids; the coupling solves for them instead).
/// A domain without open faces is closed: the pressure is then defined up to a constant
/// (projection.hpp handles it).
#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"

namespace tetfsi::fluid {

enum class FaceKind { kWall, kInflow, kOpen, kInterface };
/// Node condition, by priority open > interface > inflow > wall > interior.
enum class NodeKind { kInterior, kWall, kInflow, kInterface, kOpen };

/// Axis-aligned box [lo, hi] [m]; a point is inside within `tolerance`.
struct Region {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = Eigen::Vector3d::Zero();
  bool contains(const Eigen::Vector3d& x, double tolerance = 1e-9) const {
    return (x.array() >= lo.array() - tolerance).all() && (x.array() <= hi.array() + tolerance).all();
  }
};

/// A patch of the OUTER boundary: every outer face whose centroid lies in `region`.
struct BoundaryPatch {
  Region region;
  FaceKind kind = FaceKind::kWall;               ///< kWall, kInflow or kOpen
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< inflow velocity [m/s]
  /// If set, the inflow velocity at each face vertex instead of `velocity` (a non-uniform far field).
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> velocity_field;
  double smoke = 0.0;                             ///< inflow smoke density [-]
  double temperature = 0.0;                       ///< inflow temperature [K]
  /// kWall only: no tangential stress on these faces even when the fluid's walls are no-slip (a
  /// symmetry plane; fluid/viscosity/viscous_boundary.hpp).
  bool slip = false;
};

/// A small source volume: tets whose centroid lies in `region` get this smoke and temperature
/// every step (and this velocity if `set_velocity`).
struct SourceVolume {
  Region region;
  double smoke = 1.0;
  double temperature = 0.0;
  bool set_velocity = false;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
};

struct BoundaryConditions {
  std::vector<BoundaryPatch> patches;  ///< first matching patch wins; unmatched outer faces are walls
  std::vector<SourceVolume> sources;
  /// Velocity of every TetMesh vertex on a solid interface [m/s], indexed by TetMesh vertex id;
  /// empty: solids at rest.
  std::vector<Eigen::Vector3d> solid_vertex_velocity;
  /// For a viscous fluid only (fluid/viscosity/viscous_boundary.hpp), when solid_vertex_velocity is
  /// empty: the velocity the fluid takes at solid interface vertices, indexed by TetMesh vertex id,
  /// without prescribing any flux (the coupled step passes the solids' uⁿ here; their flux is the
  /// coupled system's unknown). Empty: solids at rest.
  std::vector<Eigen::Vector3d> no_slip_velocity;
  /// Closed domains only: if the prescribed fluxes do not sum to zero (the P1 quadrature of a
  /// non-linear far field such as BoundaryPatch::velocity_field is not exactly conservative),
  /// subtract the net flux from the INFLOW-patch nodes in proportion to |f_i| there. Off: a net
  /// inflow into a closed domain is an error (projection.hpp).
  bool balance_inflow = false;
};

/// Result of applying BoundaryConditions to one FluidMesh.
struct ClassifiedBoundary {
  std::vector<FaceKind> face_kind;       ///< per mesh.boundary_faces
  std::vector<int> face_patch;           ///< patch index per boundary face, -1 if none
  std::vector<NodeKind> node_kind;       ///< per fluid node
  std::vector<int> flux_faces;           ///< faces with prescribed nonzero-capable normal velocity
  std::vector<std::array<Eigen::Vector3d, 3>> flux_velocity;  ///< their vertex velocities [m/s]
  Eigen::VectorXd flux;                  ///< f_i = int phi_i u_b.n dA over flux faces [m^3/s]
  bool closed = true;                    ///< no open node: pressure has a constant null space
  double flux_imbalance = 0.0;           ///< net flux removed by balance_inflow / sum |f| [-]
};

/// Index of the first patch of `bc` whose region holds the centroid of outer boundary face `face`
/// (a face not shared with a solid), -1 if none (a wall).
int outer_face_patch(const FluidMesh& mesh, const BoundaryConditions& bc, const BoundaryFace& face);

/// What a semi-Lagrangian back-trace reads where it leaves the fluid through a boundary face
/// (semi_lagrangian.hpp): the state of the fluid that enters through that face during the step.
///  - kClamp (walls, solid interfaces, uniform inflow patches): the reconstructed value at the
///    boundary point.
///  - kInflow (inflow patches with a velocity_field, e.g. a parabolic profile): the prescribed
///    velocity at the boundary point (the Dirichlet data of the fluid that enters), interpolated
///    linearly from the face's vertices, so that the profile is carried into the domain: an inviscid
///    projection alone only imposes u.n, and from a fluid at rest it gives the irrotational
///    (uniform) flow. Uniform patches keep kClamp: reading their velocity too is as right, but it
///    changes the validated jet scenes (the bar between two jets, bar_compare_ci, buffets 3.6 mm
///    instead of under 1.7 mm in its first second), which have not been re-measured with it.
///  - kOpen (p = 0): backflow keeps only its normal component, u = (u.n) n where u.n < 0; outflow
///    traces do not leave through the face. This is OpenFOAM's pressureInletOutletVelocity (zero
///    gradient for outflow; for inflow the face-normal component of the interior value). With p = 0
///    the fluid re-entering through an open face brings the kinetic-energy flux -1/2 rho |u|^2 (u.n)
///    per unit area and does no work against the pressure: the backflow instability of the
///    do-nothing condition (Braack & Mucha 2014, J. Comput. Math. 32(5) 507-521; Bazilevs et al.
///    2009, Comput. Methods Appl. Mech. Engrg. 198, 3534-3550). Clamping extrapolates the interior's
///    tangential velocity into the entering fluid (zero gradient), so a vortex crossing the face
///    feeds itself; dropping the tangential part limits the flux to -1/2 rho (u.n)^2 (u.n).
enum class ExitRule : unsigned char { kClamp, kOpen, kInflow };

/// ExitRule per boundary face of one FluidMesh.
struct BoundaryExits {
  std::vector<ExitRule> rule;  ///< per mesh.boundary_faces
  /// kInflow faces: the prescribed velocity at the face's nodes (BoundaryFace::nodes order) [m/s];
  /// other faces: unused.
  std::vector<std::array<Eigen::Vector3d, 3>> inflow_velocity;
};

/// The exit rules of `mesh`'s boundary faces under `bc` (the patches only; solid velocities unused).
BoundaryExits boundary_exits(const FluidMesh& mesh, const BoundaryConditions& bc);

/// Classifies faces and nodes and assembles the boundary flux.
/// @throws std::invalid_argument if solid_vertex_velocity is non-empty but too short
ClassifiedBoundary classify_boundary(const FluidMesh& mesh, const BoundaryConditions& bc);

}  // namespace tetfsi::fluid
