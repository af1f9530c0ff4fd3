#include "solid/contact/static_obstacles.hpp"

#include <Eigen/Geometry>
#include <limits>

#include "solid/solid_error.hpp"

namespace tetfsi::solid {

void StaticObstacles::add_plane(const PlaneObstacle& plane) {
  const double n = plane.normal.norm();
  if (!(n > 0) || !plane.point.allFinite()) throw SolidError("plane obstacle: normal must be non-zero and finite");
  planes_.push_back({plane.point, plane.normal / n});
}

void StaticObstacles::add_box(const BoxObstacle& box) {
  if (!((box.hi - box.lo).minCoeff() > 0)) throw SolidError("box obstacle: need hi > lo on every axis");
  boxes_.push_back(box);
}

void StaticObstacles::add_sphere_interior(const SphereInteriorObstacle& sphere) {
  if (!(sphere.radius > 0) || !sphere.center.allFinite()) throw SolidError("sphere obstacle: radius must be > 0");
  spheres_.push_back(sphere);
}

void StaticObstacles::add_cylinder_interior(const CylinderInteriorObstacle& cylinder) {
  const double a = cylinder.axis.norm();
  if (!(cylinder.radius > 0) || !(a > 0) || !cylinder.center.allFinite())
    throw SolidError("cylinder obstacle: radius must be > 0 and the axis non-zero");
  cylinders_.push_back({cylinder.center, cylinder.axis / a, cylinder.radius});
}

void StaticObstacles::set_friction(double mu) {
  if (!(mu >= 0)) throw SolidError("contact friction coefficient must be >= 0");
  friction_ = mu;
}

void StaticObstacles::add_implicit(const ImplicitObstacle& obstacle) {
  if (!obstacle.distance) throw SolidError("implicit obstacle: no distance function");
  implicits_.push_back(obstacle);
}

double StaticObstacles::signed_distance(const Eigen::Vector3d& x, Eigen::Vector3d& normal) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& p : planes_) {
    const double phi = (x - p.point).dot(p.normal);
    if (phi < best) {
      best = phi;
      normal = p.normal;
    }
  }
  for (const auto& b : boxes_) {
    // Inside: distance to the nearest face (negative); outside: Euclidean distance.
    const Eigen::Vector3d c = 0.5 * (b.lo + b.hi), half = 0.5 * (b.hi - b.lo);
    const Eigen::Vector3d q = (x - c).cwiseAbs() - half;
    double phi;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    if (q.maxCoeff() < 0) {
      int axis;
      phi = q.maxCoeff(&axis);
      n[axis] = x[axis] >= c[axis] ? 1.0 : -1.0;
    } else {
      const Eigen::Vector3d outside = q.cwiseMax(0.0);
      phi = outside.norm();
      for (int k = 0; k < 3; ++k) n[k] = (x[k] >= c[k] ? 1.0 : -1.0) * outside[k];
      n /= phi > 0 ? phi : 1.0;
    }
    if (phi < best) {
      best = phi;
      normal = n;
    }
  }
  for (const auto& sp : spheres_) {
    const Eigen::Vector3d r = x - sp.center;
    const double phi = sp.radius - r.norm();
    if (phi < best) {
      best = phi;
      normal = r.norm() > 0 ? Eigen::Vector3d(-r.normalized()) : Eigen::Vector3d::UnitZ();
    }
  }
  for (const auto& c : cylinders_) {
    Eigen::Vector3d r = x - c.center;
    r -= r.dot(c.axis) * c.axis;  // the radial part
    const double phi = c.radius - r.norm();
    if (phi < best) {
      best = phi;
      normal = r.norm() > 0 ? Eigen::Vector3d(-r.normalized()) : c.axis.unitOrthogonal();
    }
  }
  for (const auto& o : implicits_) {
    Eigen::Vector3d n;
    const double phi = o.distance(x, n);
    if (phi < best) {
      best = phi;
      normal = n;
    }
  }
  return best;
}

int StaticObstacles::project(const Eigen::VectorXd& X, Eigen::VectorXd& d, Eigen::VectorXd& u,
                             const std::vector<char>& fixed) const {
  if (empty()) return 0;
  int contacts = 0;
  const int n = static_cast<int>(X.size() / 3);
  for (int v = 0; v < n; ++v) {
    if (!fixed.empty() && (fixed[3 * v] || fixed[3 * v + 1] || fixed[3 * v + 2])) continue;
    Eigen::Vector3d normal;
    const double phi = signed_distance(X.segment<3>(3 * v) + d.segment<3>(3 * v), normal);
    if (!(phi < 0)) continue;
    ++contacts;
    d.segment<3>(3 * v) -= phi * normal;
    Eigen::Vector3d vel = u.segment<3>(3 * v);
    const double vn = vel.dot(normal);
    if (vn < 0) {
      vel -= vn * normal;
      const double vt = vel.norm();
      if (friction_ > 0 && vt > 0) vel *= std::max(0.0, 1.0 - friction_ * (-vn) / vt);
      u.segment<3>(3 * v) = vel;
    }
  }
  return contacts;
}

}  // namespace tetfsi::solid
