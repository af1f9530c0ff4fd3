#pragma once
/// @file static_obstacles.hpp
/// Contact of solid nodes with static obstacles: half-spaces (floor planes), axis-aligned
/// boxes, the insides of spheres and cylinders (vessels), and signed-distance functions (the
/// inside of a vessel read from a surface file).
///
/// The primary contact treatment is inside the implicit solve (NewmarkIntegrator::step():
/// active set of landing constraints, inelastic normal, Coulomb friction from the constraint
/// force). This class gives the geometry (signed distance, normal) and the fallback used after
/// every update (and the only one when a caller uses form_system/advance directly):
/// a post-step projection (in the spirit of Bridson, Fedkiw & Anderson 2002, applied
/// to static obstacles). After the update of eq. (5), every node x = X + d inside an obstacle
/// (signed distance phi < 0, outward normal n) is moved to the surface, d += -phi n, and if it
/// approaches (v_n = u.n < 0) its normal velocity is removed (perfectly inelastic contact).
/// Coulomb friction with coefficient mu then reduces the tangential velocity u_t by the
/// impulse the normal correction provides: u_t <- max(0, 1 - mu |v_n| / |u_t|) u_t.
/// The projection only removes kinetic energy and moves nodes by at most their penetration,
/// so it is stable for any time step (it does not enter the linear system, which keeps the
/// coupled system of eq. (4) unchanged). Limitation: nodes only; an obstacle edge can still
/// cut through a large solid face between nodes.
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace tetfsi::solid {

/// Solid lives on the side the normal points to: phi(x) = (x - point).n.
struct PlaneObstacle {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< normalized on construction of StaticObstacles
};

/// Solid stays outside the box [lo, hi].
struct BoxObstacle {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d hi = Eigen::Vector3d::Ones();
};

/// Solid stays inside the ball |x − center| <= radius (a spherical vessel): φ = radius − |x − center|.
struct SphereInteriorObstacle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 1;
};

/// Solid stays within `radius` of the line through `center` along `axis` (the side wall of a
/// cylindrical vessel; its ends are planes): φ = radius − |(x − center) − ((x − center)·a) a|.
struct CylinderInteriorObstacle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< normalized on construction of StaticObstacles
  double radius = 1;
};

/// An obstacle given by a signed-distance function: `distance(x, normal)` returns phi(x) [m],
/// positive on the side the solid lives on, and sets the unit normal pointing to that side (e.g.
/// the inside of a closed surface read from a file: phi = -d(x) - gap with d the surface's signed
/// distance, negative inside, and n = (x - y)/|x - y| for its nearest point y inside, (y - x)/|y - x|
/// outside). Called from one thread.
struct ImplicitObstacle {
  std::function<double(const Eigen::Vector3d& x, Eigen::Vector3d& normal)> distance;
};

class StaticObstacles {
 public:
  /// @throws SolidError on a zero normal, a box with hi <= lo, or a negative friction
  void add_plane(const PlaneObstacle& plane);
  void add_box(const BoxObstacle& box);
  /// @throws SolidError on a radius <= 0 (or a zero axis)
  void add_sphere_interior(const SphereInteriorObstacle& sphere);
  void add_cylinder_interior(const CylinderInteriorObstacle& cylinder);
  /// @throws SolidError on an empty function
  void add_implicit(const ImplicitObstacle& obstacle);
  void set_friction(double mu);
  double friction() const { return friction_; }
  bool empty() const {
    return planes_.empty() && boxes_.empty() && spheres_.empty() && cylinders_.empty() && implicits_.empty();
  }

  /// Signed distance to the nearest obstacle surface (negative inside) and its outward normal.
  double signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const;

  /// Projects nodes out of the obstacles and corrects their velocities (see file comment).
  /// @param X      reference positions, 3n [m]
  /// @param d, u   displacement [m] and velocity [m/s], 3n, modified in place
  /// @param fixed  per-DOF Dirichlet flags (nodes with any fixed DOF are left alone), or empty
  /// @return number of nodes in contact
  int project(const Eigen::VectorXd& X, Eigen::VectorXd& d, Eigen::VectorXd& u,
              const std::vector<char>& fixed) const;

 private:
  std::vector<PlaneObstacle> planes_;
  std::vector<BoxObstacle> boxes_;
  std::vector<SphereInteriorObstacle> spheres_;
  std::vector<CylinderInteriorObstacle> cylinders_;
  std::vector<ImplicitObstacle> implicits_;
  double friction_ = 0;
};

}  // namespace tetfsi::solid
