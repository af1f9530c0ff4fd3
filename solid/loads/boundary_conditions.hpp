#pragma once
/// @file boundary_conditions.hpp
/// Boundary conditions and loads of a solid (tet or hex8 mesh), given per node set or per set of
/// boundary faces (surface_face.hpp). Values are given at load factor lambda = 1; the static
/// solver (solid/analysis/static_solver.hpp) scales them with lambda (prescribed rotations: the
/// angle is scaled), the dynamic runs apply them at lambda = 1, constant in time.
///
/// Loads:
///  - nodal forces and dead surface tractions, consistent: f_a = int_face N_a t dA (reference faces);
///  - body force b [N/m^3] (per reference volume, dead): f_a = int N_a b dV = (m_a / rho) b, the
///    lumped masses m_a = rho int N_a dV of the model;
///  - follower pressure p [Pa] on boundary faces, acting on the deformed surface against its outward
///    normal: f_a = -p int_face(x) N_a n da = -p sum_g w_g N_a(g) (x_s x x_t)(g) (follower_pressure.hpp).
///
/// End moments. Two forms are offered:
///  - add_end_moment_traction(): a dead (non-follower) linear normal traction
///      t = sigma n,  sigma = (M / I) (X - c) . (n x a),  I = int ((X - c) . (n x a))^2 dA,
///    on the reference end face (n its normal, a the moment axis, c the face centroid), whose
///    resultant is the pure couple M a. Valid while the end rotation stays small: it does not turn
///    with the section.
///  - RotatingFace: the end face turns rigidly by a prescribed angle lambda theta about an axis
///    while translating freely (3 shared unknowns t):  u_i = (R(lambda theta) - I)(X_i - c) + t.
///    Because t is free the constraint transmits no net force, only a couple (the reaction moment
///    StaticResult reports), so this is the pure end moment of the elastica, and it turns with the
///    section. It is displacement control of the rotation, conservative and with a symmetric
///    tangent. This is what the roll-up to a full circle uses: the end
///    rotation of the elastica is theta = M L / (EI), and M is read back as the reaction.
#include <Eigen/Core>
#include <functional>
#include <utility>
#include <vector>

#include "solid/loads/surface_face.hpp"

namespace tetfsi::solid {

/// A node set turning rigidly about `axis` through `center` by lambda * `angle` with a free
/// common translation (see the file comment).
struct RotatingFace {
  std::vector<int> nodes;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< reference point on the axis [m]
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< rotation axis (normalised on use)
  double angle = 0.0;                                ///< rotation at lambda = 1 [rad]
};

/// Follower pressure `pressure` [Pa] (at lambda = 1) on outward boundary faces.
struct PressureLoad {
  std::vector<SurfaceFace> faces;
  double pressure = 0.0;
};

struct BoundaryConditions {
  std::vector<int> fixed_dofs;                       ///< dofs held at 0 (dof = 3 node + component)
  std::vector<std::pair<int, double>> prescribed;    ///< (dof, displacement at lambda = 1 [m])
  std::vector<RotatingFace> rotating_faces;
  Eigen::VectorXd forces;                            ///< dead nodal loads at lambda = 1 [N]; empty = none
  std::vector<PressureLoad> pressures;               ///< follower loads at lambda = 1
};

/// Holds all 3 components of `nodes` at zero.
void fix_nodes(BoundaryConditions& bc, const std::vector<int>& nodes);
/// Holds component `component` (0, 1, 2) of `nodes` at zero.
void fix_component(BoundaryConditions& bc, const std::vector<int>& nodes, int component);
/// Prescribes displacement `u` (at lambda = 1) on all 3 components of `nodes`.
void prescribe_displacement(BoundaryConditions& bc, const std::vector<int>& nodes, const Eigen::Vector3d& u);
/// Adds a nodal force `f` [N] to each node of `nodes`.
void add_nodal_force(BoundaryConditions& bc, int num_nodes, const std::vector<int>& nodes, const Eigen::Vector3d& f);
/// Adds the consistent nodal forces of a dead surface traction t(X) [Pa] on reference faces:
/// f_a = int_face N_a t dA (surface_face.hpp quadrature).
void add_surface_traction(BoundaryConditions& bc, const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<SurfaceFace>& faces,
                          const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& traction);
/// Dead linear traction with resultant couple `moment` [N m] about `axis` (see the file comment).
/// The faces must be planar and share one normal. @throws std::invalid_argument otherwise.
void add_end_moment_traction(BoundaryConditions& bc, const std::vector<Eigen::Vector3d>& vertices,
                             const std::vector<SurfaceFace>& faces, const Eigen::Vector3d& axis, double moment);
/// Dead body force `b` [N/m^3] on `nodes`: f_a += (m_a / rho) b with the model's lumped masses
/// `masses` [kg] and density `density` [kg/m^3].
void add_body_force(BoundaryConditions& bc, const Eigen::VectorXd& masses, double density,
                    const std::vector<int>& nodes, const Eigen::Vector3d& b);

}  // namespace tetfsi::solid
