// The container's walls as contact planes (apps/run/container.hpp, coupling.wall_contact): each
// plane is a face of the container set back by the gap, its normal into the fluid, so a point is
// inside the container less the gap exactly when every plane's φ(x) = (x − point)·n is positive.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "apps/run/container.hpp"

using tetfsi::scene::Json;

namespace {

double min_phi(const std::vector<tetfsi::solid::PlaneObstacle>& planes, const Eigen::Vector3d& x) {
  double phi = std::numeric_limits<double>::infinity();
  for (const auto& p : planes) phi = std::min(phi, (x - p.point).dot(p.normal));
  return phi;
}

}  // namespace

TEST(ContainerWalls, BoxFacesSetBackByTheGap) {
  const Json domain = {{"lo", {-1, -2, -3}}, {"hi", {1, 2, 3}}};
  const auto planes = tetfsi::run::container_wall_planes(domain, 0.1);
  ASSERT_EQ(planes.size(), 6u);
  EXPECT_NEAR(min_phi(planes, Eigen::Vector3d::Zero()), 0.9, 1e-14);             // nearest: the x faces
  EXPECT_NEAR(min_phi(planes, Eigen::Vector3d(0, -1.9, 0)), 0.0, 1e-14);        // on the floor's plane
  EXPECT_NEAR(min_phi(planes, Eigen::Vector3d(0, 0, 2.95)), -0.05, 1e-14);      // inside the film
}

TEST(ContainerWalls, CylinderIsItsCapsAndOnePlanePerSide) {
  // A 12-sided prism along y: 12 sides (two triangles each, merged) and two caps (many triangles, merged).
  const Json domain = {{"lo", {-1, -1, -1}},
                       {"hi", {1, 1, 1}},
                       {"container",
                        {{"type", "cylinder"}, {"center", {0, 0, 0}}, {"radius", 0.5}, {"length", 1.0},
                         {"segments", 12}, {"axis", "y"}}}};
  const auto planes = tetfsi::run::container_wall_planes(domain, 0.05);
  EXPECT_EQ(planes.size(), 14u);
  // The centre is 0.5 cos(15°) − 0.05 from the nearest side's plane (and 0.45 from the caps).
  EXPECT_NEAR(min_phi(planes, Eigen::Vector3d::Zero()), 0.5 * std::cos(std::acos(-1.0) / 12) - 0.05, 1e-12);
  // A point on the axis near a cap; a point just outside the set-back side.
  EXPECT_NEAR(min_phi(planes, Eigen::Vector3d(0, 0.44, 0)), 0.01, 1e-12);
  EXPECT_LT(min_phi(planes, Eigen::Vector3d(0.46, 0, 0)), 0.0);
  for (const auto& p : planes) EXPECT_NEAR(p.normal.norm(), 1.0, 1e-12);
}

TEST(ContainerWalls, SphereKeepsEveryPointOfTheInnerBallInside) {
  const Json domain = {{"lo", {-1, -1, -1}},
                       {"hi", {1, 1, 1}},
                       {"container", {{"type", "sphere"}, {"center", {0.1, 0, 0}}, {"radius", 0.5}, {"subdivisions", 2}}}};
  const auto planes = tetfsi::run::container_wall_planes(domain, 0.02);
  EXPECT_GT(planes.size(), 100u);
  // The icosphere's faces lie inside the sphere, within their sagitta: a point 0.1 inside the
  // sphere less the gap is inside every plane, a point beyond the radius is outside one.
  for (const Eigen::Vector3d dir : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1, 1, 1).normalized()}) {
    EXPECT_GT(min_phi(planes, Eigen::Vector3d(0.1, 0, 0) + 0.38 * dir), 0.0);
    EXPECT_LT(min_phi(planes, Eigen::Vector3d(0.1, 0, 0) + 0.5 * dir), 0.0);
  }
}
