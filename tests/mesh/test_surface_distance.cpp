// mesh::SurfaceDistance, the signed distance to a closed surface file:
//  - a box surface gives the exact box distance (outside: the distance to the nearest point of the
//    box; inside: minus the distance to the nearest face) to 1e-12 of the box size, at 500 points;
//  - an icosphere of radius r (4 subdivisions) gives |x| - r within the polyhedron's deviation from
//    the sphere (its largest edge e: r - sqrt(r^2 - e^2/3) bounds the sagitta), with the right sign.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "mesh/primitives.hpp"
#include "mesh/surface_distance.hpp"

using namespace tetfsi::mesh;

namespace {

/// Exact signed distance to the axis-aligned box [-a, a] (a = half extents).
double box_distance(const Eigen::Vector3d& x, const Eigen::Vector3d& a) {
  const Eigen::Vector3d q = x.cwiseAbs() - a;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

}  // namespace

TEST(SurfaceDistance, BoxSurfaceGivesTheExactBoxDistance) {
  const Eigen::Vector3d size(0.4, 0.6, 2.0);
  const SurfaceDistance distance(make_box(size));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int inside = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    const double exact = box_distance(x, size / 2);
    EXPECT_NEAR(distance(x), exact, 1e-12 * size.norm()) << x.transpose();
    inside += exact < 0;
  }
  EXPECT_GT(inside, 10);  // both signs were tested
}

TEST(SurfaceDistance, IcosphereApproachesTheSphereDistance) {
  const double r = 0.3;
  const SurfaceMesh sphere = make_sphere(r, 4);
  double longest = 0;
  for (const auto& t : sphere.triangles)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (sphere.vertices[t[k]] - sphere.vertices[t[(k + 1) % 3]]).norm());
  const double sagitta = r - std::sqrt(r * r - longest * longest / 3);
  const SurfaceDistance distance(sphere);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    const double exact = x.norm() - r;
    const double d = distance(x);
    EXPECT_LE(d, exact + sagitta + 1e-12) << x.transpose();  // the polyhedron lies inside the sphere
    EXPECT_GE(d, exact - 1e-12) << x.transpose();
    if (std::abs(exact) > sagitta) EXPECT_EQ(d < 0, exact < 0) << x.transpose();
  }
}

TEST(SurfaceDistance, RefusesAnEmptySurface) { EXPECT_THROW(SurfaceDistance{SurfaceMesh{}}, MeshError); }
