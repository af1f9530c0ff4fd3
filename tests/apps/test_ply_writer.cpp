// PLY export: the file read back (header parsed by an independent reader) has the counts,
// positions, velocities and triangles written, to float32 precision.
#include <gtest/gtest.h>

#include "mesh/io/ply_writer.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

using tetfsi::mesh::SurfaceMesh;

TEST(PlyWriter, RoundTripWithVelocity) {
  tetfsi::test::TempDir dir("ply");
  SurfaceMesh s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1.25}};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::vector<Eigen::Vector3d> v = {{1, 2, 3}, {-1, 0, 0.5}, {0, 0, 0}, {1e-3, 2e-3, -4}};
  const auto file = dir.path() / "t.ply";
  tetfsi::mesh::io::write_ply(file, s, v);
  const auto d = tetfsi::test::read_ply(file);
  ASSERT_EQ(d.positions.size(), 4u);
  ASSERT_EQ(d.velocities.size(), 4u);
  ASSERT_EQ(d.triangles.size(), 4u);
  EXPECT_EQ(d.vertex_properties, (std::vector<std::string>{"x", "y", "z", "vx", "vy", "vz"}));
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((d.positions[i] - s.vertices[i]).norm(), 1e-6);
    EXPECT_LT((d.velocities[i] - v[i]).norm(), 1e-6);
    EXPECT_EQ(d.triangles[i], s.triangles[i]);
  }
}

TEST(PlyWriter, WithoutVelocityAndBadInput) {
  tetfsi::test::TempDir dir("ply");
  SurfaceMesh s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.triangles = {{0, 1, 2}};
  tetfsi::mesh::io::write_ply(dir.path() / "a.ply", s);
  const auto d = tetfsi::test::read_ply(dir.path() / "a.ply");
  EXPECT_EQ(d.vertex_properties.size(), 3u);
  EXPECT_TRUE(d.velocities.empty());
  EXPECT_THROW(tetfsi::mesh::io::write_ply(dir.path() / "b.ply", s, {{0, 0, 0}}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "b.ply"));
}
