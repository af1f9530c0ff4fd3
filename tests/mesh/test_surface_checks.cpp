// Open, non-manifold, inconsistently oriented, inward and self-intersecting surfaces are each
// rejected (or, for inward, flipped) with a message naming the input and the defect.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "mesh/primitives.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_import.hpp"

using namespace tetfsi::mesh;

namespace {

/// Union of two surfaces as one triangle list, vertices at identical positions joined (so that
/// boxes touching at an edge or a corner really share it).
SurfaceMesh merged(const SurfaceMesh& a, const SurfaceMesh& b) {
  SurfaceMesh out;
  std::map<std::array<double, 3>, int> index;
  for (const SurfaceMesh* s : {&a, &b}) {
    std::vector<int> local;
    for (const auto& v : s->vertices) {
      auto [it, inserted] = index.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, out.num_vertices());
      if (inserted) out.vertices.push_back(v);
      local.push_back(it->second);
    }
    for (const auto& t : s->triangles) out.triangles.push_back({local[t[0]], local[t[1]], local[t[2]]});
  }
  return out;
}

SurfaceMesh unit_box_at(const Eigen::Vector3d& centre) {
  SurfaceMesh s = make_box({1, 1, 1});
  for (auto& v : s.vertices) v += centre;
  return s;
}

/// Runs validate_surface and returns the error message ("" if it passed).
std::string error_of(SurfaceMesh s, const std::string& name = "model.obj") {
  try {
    validate_surface(s, name);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

void expect_contains(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos) << "message: \"" << message << "\" lacks \"" << part << "\"";
}

}  // namespace

TEST(SurfaceChecks, ValidShapesPass) {
  EXPECT_EQ(error_of(make_box({1, 2, 3})), "");
  EXPECT_EQ(error_of(make_sphere(1, 3)), "");
  EXPECT_EQ(error_of(import_surface(TETFSI_SHARED_DIR "/data/bunny.obj")), "");
}

TEST(SurfaceChecks, BowlIsClosedOutwardAndEnclosesTheShellsVolume) {
  // A hemispherical shell: volume (2π/3)(R³ − r³), approached from below by the inscribed rings
  // (second order in the ring spacing).
  const double R = 0.2, t = 0.03, r = R - t, exact = 2.0 * std::acos(-1.0) / 3.0 * (R * R * R - r * r * r);
  SurfaceMesh coarse = make_bowl(R, t, 24, 6), fine = make_bowl(R, t, 48, 12);
  EXPECT_EQ(coarse.num_triangles(), 4 * 24 * 6);
  EXPECT_EQ(error_of(coarse, "bowl"), "");
  EXPECT_EQ(error_of(fine, "bowl"), "");
  const double e_coarse = (exact - enclosed_volume(coarse)) / exact, e_fine = (exact - enclosed_volume(fine)) / exact;
  std::printf("bowl volume: relative error %.3g (24 x 6), %.3g (48 x 12)\n", e_coarse, e_fine);
  EXPECT_GT(e_coarse, 0);
  EXPECT_LT(e_coarse, 0.035);  // measured 0.0282; the fine one 0.00712
  EXPECT_NEAR(e_fine / e_coarse, 0.25, 0.02);  // second order
  Eigen::Vector3d lo, hi;
  bounding_box(fine, lo, hi);
  EXPECT_NEAR(lo.y(), -R, 1e-15);
  EXPECT_NEAR(hi.y(), 0.0, 1e-15);
}

TEST(SurfaceChecks, OpenSurfaceIsRejected) {
  SurfaceMesh s = make_box({1, 1, 1});
  s.triangles.pop_back();  // triangle {1, 7, 5}: its 3 edges lose their second triangle
  const std::string msg = error_of(s);
  expect_contains(msg, "model.obj");
  expect_contains(msg, "not closed: 3 boundary edges");
}

TEST(SurfaceChecks, NonManifoldEdgeIsRejected) {
  // Two boxes sharing one edge: that edge is in 4 triangles.
  const std::string msg = error_of(merged(unit_box_at({0, 0, 0}), unit_box_at({1, 1, 0})));
  expect_contains(msg, "model.obj: non-manifold: 1 edges in more than two triangles");
  expect_contains(msg, "(in 4 triangles)");
}

TEST(SurfaceChecks, NonManifoldVertexIsRejected) {
  // Two boxes sharing one corner: every edge is fine, the corner has two separate fans.
  const std::string msg = error_of(merged(unit_box_at({0, 0, 0}), unit_box_at({1, 1, 1})));
  expect_contains(msg, "model.obj: non-manifold: 1 vertices where separate surface sheets touch");
}

TEST(SurfaceChecks, InconsistentOrientationIsRejected) {
  SurfaceMesh s = make_sphere(1, 1);
  std::swap(s.triangles[7][1], s.triangles[7][2]);
  const std::string msg = error_of(s);
  expect_contains(msg, "model.obj: inconsistently oriented: 3 edges");
  expect_contains(msg, "triangle");
}

TEST(SurfaceChecks, InwardSurfaceIsFlippedWithAWarning) {
  SurfaceMesh s = make_sphere(1, 2);
  const double volume = enclosed_volume(s);
  flip_orientation(s);
  const auto warnings = validate_surface(s, "ball.stl");
  ASSERT_EQ(warnings.size(), 1u);
  expect_contains(warnings[0], "ball.stl: surface was oriented inward");
  EXPECT_NEAR(enclosed_volume(s), volume, 1e-12);
}

TEST(SurfaceChecks, SelfIntersectionIsRejected) {
  // Two overlapping boxes as one surface: closed, manifold, oriented, but the sheets cross.
  const std::string msg = error_of(merged(unit_box_at({0, 0, 0}), unit_box_at({0.5, 0.3, 0.2})), "two_boxes.ply");
  expect_contains(msg, "two_boxes.ply: self-intersecting:");
  expect_contains(msg, "intersecting triangle pairs, e.g. triangles ");
}

TEST(SurfaceChecks, OtherDefectsAreNamed) {
  SurfaceMesh s = make_box({1, 1, 1});
  s.triangles[0][2] = 99;
  expect_contains(error_of(s), "vertex index out of range");
  s = make_box({1, 1, 1});
  s.triangles[0][2] = s.triangles[0][1];
  expect_contains(error_of(s), "degenerate triangles");
  expect_contains(error_of(SurfaceMesh{}), "no triangles");
}

TEST(SurfaceChecks, DisjointAndOverlappingSolids) {
  EXPECT_FALSE(surfaces_intersect(unit_box_at({0, 0, 0}), unit_box_at({2, 0, 0})));
  EXPECT_TRUE(surfaces_intersect(unit_box_at({0, 0, 0}), unit_box_at({0.5, 0, 0})));
  // Nested: no triangle crosses, but one solid contains the other.
  SurfaceMesh small = make_sphere(0.1, 1);
  EXPECT_TRUE(surfaces_intersect(unit_box_at({0, 0, 0}), small));
}
