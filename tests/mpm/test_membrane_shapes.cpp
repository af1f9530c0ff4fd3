// Membrane shapes of the `mpm` block (apps/mpm/membrane_shapes.hpp): every primitive is a
// consistently oriented quad surface with the expected area or enclosed volume, the closed ones
// have no free edge and outward normals, a cut by symmetry planes keeps the same nodes, and a
// triangle surface split into quads keeps its geometry exactly.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "apps/mpm/membrane_shapes.hpp"

using namespace tetfsi;
using mpm_setup::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;

double area(const mpm_setup::QuadMesh& m) {
  double a = 0;
  for (const auto& q : m.quads) {
    const Vec3 &p0 = m.nodes[q[0]], &p1 = m.nodes[q[1]], &p2 = m.nodes[q[2]], &p3 = m.nodes[q[3]];
    a += 0.5 * ((p1 - p0).cross(p2 - p0).norm() + (p2 - p0).cross(p3 - p0).norm());
  }
  return a;
}

void expect_closed(const mpm_setup::QuadMesh& m, const std::vector<mpm_setup::SymmetryPlane>& planes = {}) {
  EXPECT_EQ(mpm_setup::non_manifold_or_misoriented_edges(m.quads), 0);
  EXPECT_TRUE(mpm_setup::open_edges(m.nodes, m.quads, planes, 1e-12).empty());
}

}  // namespace

TEST(MembraneShapes, OpenPrimitivesHaveTheirArea) {
  // Disc: the concentric map puts the boundary nodes on the circle, so the polygon area of the
  // m-gon (m = 4 x 20 boundary edges) is (m / 2) R^2 sin(2 pi / m) to within the map's chords.
  const auto disc = mpm_setup::disc_mesh(Vec3(1, 2, 3), Vec3(0, 0, 1), 0.5, 0.05);
  EXPECT_EQ(mpm_setup::non_manifold_or_misoriented_edges(disc.quads), 0);
  EXPECT_NEAR(area(disc) / (kPi * 0.25), 1.0, 0.02);
  for (const auto& e : mpm_setup::open_edges(disc.nodes, disc.quads, {}, 1e-12))
    EXPECT_NEAR((disc.nodes[e[0]] - Vec3(1, 2, 3)).norm(), 0.5, 1e-12);
  // Cylinder (open tube): perimeter of the inscribed polygon, nc 2 R sin(pi / nc), times the length.
  const auto tube = mpm_setup::cylinder_mesh(Vec3(0, 0, 0), Vec3(0, 0, 2), 0.5, 0.1);
  const int nc = 32;  // 4 x round(2 pi 0.5 / 4 / 0.1)
  EXPECT_EQ(tube.quads.size(), std::size_t(nc * 20));
  EXPECT_NEAR(area(tube), nc * 2 * 0.5 * std::sin(kPi / nc) * 2.0, 1e-12);
  // Box tube: perimeter x length.
  const auto box = mpm_setup::box_tube_mesh(Vec3(0, 0, 0), 2, 0.5, 1.0, 0.1, 0.1);
  EXPECT_NEAR(area(box), 2 * (1.0 + 2.0) * 0.1, 1e-12);
  EXPECT_EQ(mpm_setup::non_manifold_or_misoriented_edges(box.quads), 0);
}

TEST(MembraneShapes, ClosedPrimitivesEncloseTheirVolumeWithOutwardNormals) {
  const auto cushion = mpm_setup::box_surface_mesh(Vec3(0.1, 0.2, 0.3), Vec3(0.4, 0.3, 0.05), 0.05);
  expect_closed(cushion);
  EXPECT_NEAR(mpm_setup::enclosed_volume(cushion.nodes, cushion.quads, {}), 0.4 * 0.3 * 0.05, 1e-15);
  EXPECT_NEAR(area(cushion), 2 * (0.4 * 0.3 + 0.3 * 0.05 + 0.4 * 0.05), 1e-14);
  // Sphere: nodes on the sphere, volume of the inscribed polyhedron just below 4/3 pi R^3.
  const auto sphere = mpm_setup::sphere_mesh(Vec3(0, 0, 0), 0.1, 0.01);
  expect_closed(sphere);
  for (const auto& x : sphere.nodes) EXPECT_NEAR(x.norm(), 0.1, 1e-15);
  const double v = mpm_setup::enclosed_volume(sphere.nodes, sphere.quads, {}), v_exact = 4.0 / 3 * kPi * 1e-3;
  EXPECT_LT(v, v_exact);
  EXPECT_GT(v, 0.99 * v_exact);
}

TEST(MembraneShapes, SymmetryCutOfTheBoxTubeIsTheQuarterLine) {
  // The quarter of the gas-expansion tube (Lian et al. 2014, 7.3): the nodes (0.5, y) for
  // y = 0 ... 1 then (x, 1) for x = 0.4 ... 0, in this order, the same values as a mesh of the
  // quarter alone, and no free edge but those on the planes and at the tube's ends.
  const std::vector<mpm_setup::SymmetryPlane> planes = {{0, 0.0}, {1, 0.0}};
  const auto q = mpm_setup::clip(mpm_setup::box_tube_mesh(Vec3(0, 0, 0), 2, 0.5, 1.0, 0.1, 0.1), planes, 1e-12);
  ASSERT_EQ(q.nodes.size(), 32u);
  ASSERT_EQ(q.quads.size(), 15u);
  for (int j = 0; j <= 10; ++j) {
    EXPECT_EQ(q.nodes[j][0], 0.5);
    EXPECT_EQ(q.nodes[j][1], 1.0 * j / 10);
  }
  for (int i = 4; i >= 0; --i) {
    EXPECT_EQ(q.nodes[15 - i][0], 0.5 * i / 5);
    EXPECT_EQ(q.nodes[15 - i][1], 1.0);
  }
  EXPECT_FALSE(std::signbit(q.nodes[15][0]));  // +0, not -0
  // Octant of the sphere: closed but for the three planes; 8 x its volume is the whole sphere's
  // but for the split of the (slightly warped) quads into two triangles, which mirrors with the
  // octant (2.7e-4 relative at 16 quads per cube edge).
  const std::vector<mpm_setup::SymmetryPlane> octant = {{0, 0.0}, {1, 0.0}, {2, 0.0}};
  const auto s = mpm_setup::sphere_mesh(Vec3(0, 0, 0), 0.1, 0.01);
  const auto s8 = mpm_setup::clip(s, octant, 1e-12);
  expect_closed(s8, octant);
  const double v8 = 8 * mpm_setup::enclosed_volume(s8.nodes, s8.quads, octant);
  EXPECT_NEAR(v8 / mpm_setup::enclosed_volume(s.nodes, s.quads, {}), 1.0, 5e-4);
  EXPECT_NEAR(v8 / (4.0 / 3 * kPi * 1e-3), 1.0, 0.01);
}

TEST(MembraneShapes, TrianglesBecomeThreeQuadsEachWithTheSameSurface) {
  // A closed tetrahedron (outward): 4 triangles -> 12 quads, nodes 4 + 6 midpoints + 4 centroids;
  // enclosed volume and area unchanged (each quad is planar, inside its triangle).
  mesh::SurfaceMesh t;
  t.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  t.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const auto q = mpm_setup::triangles_to_quads(t);
  EXPECT_EQ(q.quads.size(), 12u);
  EXPECT_EQ(q.nodes.size(), 14u);
  expect_closed(q);
  EXPECT_NEAR(mpm_setup::enclosed_volume(q.nodes, q.quads, {}), 1.0 / 6, 1e-15);
  EXPECT_NEAR(area(q), 1.5 + 0.5 * std::sqrt(3.0), 1e-14);
}
