// The structured box mesh fills the box exactly with positively oriented, conforming tets.
#include <gtest/gtest.h>

#include <map>

#include "mesh/structured_box.hpp"

using namespace tetfsi::mesh;

TEST(StructuredBox, VolumesSumToTheBoxAndAllPositive) {
  const TetMesh m = structured_box({0, 0, 0}, {2.0, 1.0, 0.5}, 4, 3, 2);
  EXPECT_EQ(m.num_vertices(), 5 * 4 * 3);
  EXPECT_EQ(m.num_tets(), 6 * 4 * 3 * 2);
  double total = 0;
  for (int t = 0; t < m.num_tets(); ++t) {
    const double v = signed_volume(m, t);
    EXPECT_GT(v, 0.0);
    total += v;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
}

TEST(StructuredBox, EveryInteriorFaceSharedByTwoTets) {
  const TetMesh m = structured_box({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  std::map<std::array<int, 3>, int> faces;
  for (const auto& t : m.tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f{};
      for (int i = 0, n = 0; i < 4; ++i)
        if (i != skip) f[n++] = t[i];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  int boundary = 0;
  for (const auto& [f, count] : faces) {
    EXPECT_LE(count, 2);
    if (count == 1) ++boundary;
  }
  EXPECT_EQ(boundary, 6 * 3 * 3 * 2);  // 6 sides, 3x3 squares, 2 triangles each
}
