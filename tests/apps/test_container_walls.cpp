// The container's walls as contact obstacles (apps/run/container.hpp, coupling.wall_contact): a
// point is inside the container less the gap exactly when the obstacles' signed distance
// (solid::StaticObstacles, positive on the free side) is positive; the smooth inscribed shapes
// of a sphere or cylinder container stay inside the polyhedron the fluid is meshed in.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "apps/run/container.hpp"
#include "mesh/primitives.hpp"
#include "tests/test_support.hpp"

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

TEST(ContainerWalls, MeshIsTheFileSurfaceSetBackByTheGap) {
  // The cube [-0.4, 0.4]^3 as an OBJ file: phi = (distance to the nearest face) - gap inside, the
  // normal pointing inward from that face; a node through the floor has phi < -gap and the floor's normal.
  tetfsi::test::TempDir dir("container_walls_mesh");
  const auto file = dir.path() / "cube.obj";
  {
    std::ofstream obj(file);
    for (int i = 0; i < 8; ++i)
      obj << "v " << (i & 1 ? 0.4 : -0.4) << " " << (i & 2 ? 0.4 : -0.4) << " " << (i & 4 ? 0.4 : -0.4) << "\n";
    for (const char* f : {"1 3 4", "1 4 2", "5 6 8", "5 8 7", "1 2 6", "1 6 5", "3 7 8", "3 8 4", "1 5 7", "1 7 3",
                          "2 4 8", "2 8 6"})
      obj << "f " << f << "\n";
  }
  const Json domain = {{"lo", {-1, -1, -1}},
                       {"hi", {1, 1, 1}},
                       {"container", {{"type", "mesh"}, {"file", file.string()}, {"unit_scale", 1.0},
                                      {"rotation_deg", {0, 0, 0}}, {"translation", {0, 0, 0}}}}};
  const double gap = 0.05;
  const auto walls = tetfsi::run::container_walls(domain, gap);
  ASSERT_EQ(walls.implicits.size(), 1u);
  tetfsi::solid::StaticObstacles o;
  walls.add_to(o);
  Eigen::Vector3d n;
  EXPECT_NEAR(o.signed_distance(Eigen::Vector3d(0.01, 0.02, 0.03), n), 0.4 - 0.03 - gap, 1e-6);
  EXPECT_NEAR(n.z(), -1.0, 1e-6);  // nearest face: z = 0.4, the inside is below it
  EXPECT_NEAR(o.signed_distance(Eigen::Vector3d(0.05, -0.3, -0.1), n), 0.1 - gap, 1e-6);
  EXPECT_NEAR(n.y(), 1.0, 1e-6);
  EXPECT_NEAR(o.signed_distance(Eigen::Vector3d(0.05, -0.38, -0.1), n), 0.02 - gap, 1e-6);
  EXPECT_NEAR(n.y(), 1.0, 1e-6);
  EXPECT_NEAR(o.signed_distance(Eigen::Vector3d(0.05, -0.45, -0.1), n), -0.05 - gap, 1e-6);  // through the floor
  EXPECT_NEAR(n.y(), 1.0, 1e-6);
}
