#pragma once
/// @file closest_point.hpp
/// The point of a triangle nearest to a point, by the Voronoi regions of its vertices, edges and
/// face (Ericson, Real-Time Collision Detection, 2005, sec. 5.1.5). Shared by the solids' surface
/// contact, the liquid's redistancing and the fluid's point location (the nearest boundary point).
#include <Eigen/Core>

namespace tetfsi::mesh {

struct ClosestPoint {
  Eigen::Vector3d point;   ///< y = w0 a + w1 b + w2 c
  Eigen::Vector3d weight;  ///< barycentric weights w, >= 0, summing to 1
  double distance = 0;     ///< |p − y| [m]
};

/// Closest point to p on the triangle (a, b, c) (a degenerate triangle gives a point on its hull).
inline ClosestPoint closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const auto result = [&](double wa, double wb, double wc) {
    ClosestPoint r;
    r.weight = {wa, wb, wc};
    r.point = wa * a + wb * b + wc * c;
    r.distance = (p - r.point).norm();
    return r;
  };
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return result(1, 0, 0);  // vertex a
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return result(0, 1, 0);  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const double v = d1 / (d1 - d3);
    return result(1 - v, v, 0);
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return result(0, 0, 1);  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const double w = d2 / (d2 - d6);
    return result(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge bc
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return result(0, 1 - w, w);
  }
  const double denom = va + vb + vc;
  if (!(denom > 0)) return result(1, 0, 0);  // degenerate triangle (zero area)
  const double v = vb / denom, w = vc / denom;
  return result(1 - v - w, v, w);
}

}  // namespace tetfsi::mesh
