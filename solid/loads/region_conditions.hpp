#pragma once
/// @file region_conditions.hpp
/// Boundary conditions and loads as a scene gives them: by kind, on the nodes or boundary faces
/// of a mesh inside a box, turned into BoundaryConditions for any solid mesh (tet or hex8).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "solid/loads/boundary_conditions.hpp"

namespace tetfsi::solid {

/// One boundary condition on the nodes (or boundary faces) inside the box [lo, hi] (+-1e-9 L).
struct RegionCondition {
  enum class Kind {
    Fixed,            ///< all components held at 0; `components` restricts to some ("xyz", "z", ...)
    Displacement,     ///< `value` [m] prescribed at lambda = 1 on `components`
    NodalForce,       ///< `value` [N] on every node of the region
    Traction,         ///< `value` [Pa], dead, on the boundary faces in the region
    MomentRotation,   ///< rigid end rotation by `angle` [rad] about `axis` through `center`, free
                      ///< translation (pure follower couple; RotatingFace)
    MomentTraction,   ///< dead linear traction with couple `moment` [N m] about `axis`
    BodyForce,        ///< `value` [N/m^3] per reference volume on the nodes in the region, dead
    Pressure,         ///< follower `pressure` [Pa] on the boundary faces in the region
  } kind = Kind::Fixed;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  std::string components = "xyz";
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< MomentRotation: a point on the axis
  double angle = 0.0;
  double moment = 0.0;
  double pressure = 0.0;
};

/// The mesh a RegionCondition list is applied to.
struct LoadedMesh {
  std::vector<Eigen::Vector3d> vertices;   ///< reference positions [m]
  std::vector<SurfaceFace> boundary;       ///< outward boundary faces
  Eigen::VectorXd masses;                  ///< lumped nodal masses [kg] (body forces)
  double density = 1.0;                    ///< [kg/m^3] (body forces: volume share m_a / rho)
};

/// Builds the boundary conditions; a dof fixed by two overlapping `Fixed` regions is kept once.
/// @throws std::invalid_argument naming the condition's index if a region selects no node (no
///         boundary face for surface loads) or `components` holds other letters than x, y, z
BoundaryConditions make_conditions(const std::vector<RegionCondition>& conditions, const LoadedMesh& mesh);

}  // namespace tetfsi::solid
