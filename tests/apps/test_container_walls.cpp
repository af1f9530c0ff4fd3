// The container's walls as contact obstacles (apps/run/container.hpp, coupling.wall_contact): a
// point is inside the container less the gap exactly when the obstacles' signed distance
// (solid::StaticObstacles, positive on the free side) is positive; the smooth inscribed shapes
// of a sphere or cylinder container stay inside the polyhedron the fluid is meshed in.
#include <gtest/gtest.h>

#include <cmath>

#include "apps/run/container.hpp"
#include "mesh/primitives.hpp"

using tetfsi::scene::Json;

namespace {

double phi(const tetfsi::run::ContainerWalls& walls, const Eigen::Vector3d& x) {
  tetfsi::solid::StaticObstacles o;
  walls.add_to(o);
  Eigen::Vector3d n;
  return o.signed_distance(x, n);
}

}  // namespace

TEST(ContainerWalls, BoxFacesSetBackByTheGap) {
  const Json domain = {{"lo", {-1, -2, -3}}, {"hi", {1, 2, 3}}};
  const auto walls = tetfsi::run::container_walls(domain, 0.1);
  ASSERT_EQ(walls.planes.size(), 6u);
  EXPECT_NEAR(phi(walls, Eigen::Vector3d::Zero()), 0.9, 1e-14);         // nearest: the x faces
  EXPECT_NEAR(phi(walls, Eigen::Vector3d(0, -1.9, 0)), 0.0, 1e-14);     // on the floor's plane
  EXPECT_NEAR(phi(walls, Eigen::Vector3d(0, 0, 2.95)), -0.05, 1e-14);   // inside the film
}

TEST(ContainerWalls, CylinderIsItsInscribedSideAndTwoCaps) {
  // A 12-sided prism of radius 0.5 along y: the inscribed circle has radius 0.5 cos(15°).
  const Json domain = {{"lo", {-1, -1, -1}},
                       {"hi", {1, 1, 1}},
                       {"container",
                        {{"type", "cylinder"}, {"center", {0.1, 0, 0}}, {"radius", 0.5}, {"length", 1.0},
                         {"segments", 12}, {"axis", "y"}}}};
  const double gap = 0.05, inradius = 0.5 * std::cos(std::acos(-1.0) / 12);
  const auto walls = tetfsi::run::container_walls(domain, gap);
  ASSERT_EQ(walls.cylinders.size(), 1u);
  ASSERT_EQ(walls.planes.size(), 2u);
  EXPECT_NEAR(phi(walls, Eigen::Vector3d(0.1, 0, 0)), inradius - gap, 1e-12);
  EXPECT_NEAR(phi(walls, Eigen::Vector3d(0.1, 0.44, 0)), 0.01, 1e-12);  // near the top cap
  EXPECT_NEAR(phi(walls, Eigen::Vector3d(0.1 + inradius, 0, 0)), -gap, 1e-12);
  // Every point the obstacles allow is inside the prism (the inscribed circle is inside it).
  const auto prism = tetfsi::run::container_surface(domain);
  for (const auto& t : prism.triangles) {
    const Eigen::Vector3d& a = prism.vertices[t[0]];
    const Eigen::Vector3d n = (prism.vertices[t[1]] - a).cross(prism.vertices[t[2]] - a).normalized();
    const Eigen::Vector3d nearest = Eigen::Vector3d(0.1, a.y(), 0) + (inradius - gap) * Eigen::Vector3d(n.x(), 0, n.z()).normalized();
    if (std::abs(n.y()) < 0.5) EXPECT_LT((nearest - a).dot(n), -gap + 1e-12);  // side faces
  }
}

TEST(ContainerWalls, SphereIsTheBallInscribedInTheIcosphere) {
  const Json domain = {{"lo", {-1, -1, -1}},
                       {"hi", {1, 1, 1}},
                       {"container", {{"type", "sphere"}, {"center", {0.1, 0, 0}}, {"radius", 0.5}, {"subdivisions", 2}}}};
  const double gap = 0.02;
  const auto walls = tetfsi::run::container_walls(domain, gap);
  ASSERT_EQ(walls.spheres.size(), 1u);
  const double r = walls.spheres[0].radius + gap;  // the inradius
  EXPECT_LT(r, 0.5);
  EXPECT_GT(r, 0.5 * 0.98);  // subdivision 2: faces within 2% of the sphere
  // The inscribed ball touches the nearest face plane and lies inside every other.
  const auto ico = tetfsi::run::container_surface(domain);
  double nearest = 1;
  for (const auto& t : ico.triangles) {
    const Eigen::Vector3d& a = ico.vertices[t[0]];
    const Eigen::Vector3d n = (ico.vertices[t[1]] - a).cross(ico.vertices[t[2]] - a).normalized();
    nearest = std::min(nearest, (a - Eigen::Vector3d(0.1, 0, 0)).dot(n));
  }
  EXPECT_NEAR(nearest, r, 1e-12);
  EXPECT_NEAR(phi(walls, Eigen::Vector3d(0.1, -0.3, 0)), r - gap - 0.3, 1e-12);
}
