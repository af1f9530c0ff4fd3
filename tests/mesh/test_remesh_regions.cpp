// band_regions (remesh_region.hpp): the regions a local remesh hands CGAL. Each must be a ball
// (CGAL's build_triangulation cones its hull to one infinite vertex); a flagged zone in several
// pieces, around a tunnel or around a cavity is still remeshed locally rather than as the whole
// mesh, which costs seconds at 10^5 tets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "mesh/quality.hpp"
#include "mesh/remesh_region.hpp"
#include "mesh/remesher.hpp"
#include "mesh/structured_box.hpp"

using namespace tetfsi::mesh;

namespace {

/// Tets of a box of unit cells whose centroid's cell (i, j, k) passes `keep`.
std::vector<char> cells(const TetMesh& box, const std::function<bool(int, int, int)>& keep) {
  std::vector<char> flagged(box.tets.size(), 0);
  for (int t = 0; t < box.num_tets(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : box.tets[t]) c += box.vertices[v] / 4.0;
    flagged[t] = keep(int(std::floor(c.x())), int(std::floor(c.y())), int(std::floor(c.z())));
  }
  return flagged;
}

double total_volume(const TetMesh& m) {
  double v = 0;
  for (int t = 0; t < m.num_tets(); ++t) v += signed_volume(m, t);
  return v;
}

long count(const std::vector<char>& flags) { return std::count(flags.begin(), flags.end(), 1); }

/// True if every flagged tet is in one of the regions and no vertex is in two regions.
bool covers_disjointly(const TetMesh& box, const std::vector<char>& flagged,
                       const std::vector<std::vector<char>>& regions) {
  std::vector<int> owners(box.num_vertices(), 0);
  for (const auto& region : regions) {
    std::vector<char> used(box.num_vertices(), 0);
    for (int t = 0; t < box.num_tets(); ++t)
      if (region[t])
        for (int v : box.tets[t]) used[v] = 1;
    for (int v = 0; v < box.num_vertices(); ++v) owners[v] += used[v];
  }
  for (int t = 0; t < box.num_tets(); ++t)
    if (flagged[t] && std::none_of(regions.begin(), regions.end(), [&](const auto& r) { return r[t] != 0; }))
      return false;
  return std::all_of(owners.begin(), owners.end(), [](int k) { return k <= 1; });
}

}  // namespace

// region_is_ball (remesh_region.hpp): CGAL's build_triangulation cones the hull of the region to
// one infinite vertex, which is a valid triangulation (Euler relation V - E + F - C = 0) only if
// the region is a ball. Two separate slabs, a block with a tunnel and a hollow block are not.
TEST(RemeshRegion, OnlyBallsAreHandedToCgal) {
  const TetMesh box = structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(3.0), 3, 3, 3);
  EXPECT_TRUE(region_is_ball(box, cells(box, [](int, int, int) { return true; })));
  EXPECT_TRUE(region_is_ball(box, cells(box, [](int i, int, int) { return i == 0; })));
  EXPECT_FALSE(region_is_ball(box, cells(box, [](int i, int, int) { return i != 1; })));                // two slabs
  EXPECT_FALSE(region_is_ball(box, cells(box, [](int i, int j, int) { return !(i == 1 && j == 1); })));  // tunnel
  EXPECT_FALSE(region_is_ball(box, cells(box, [](int i, int j, int k) { return !(i == 1 && j == 1 && k == 1); })));  // cavity
}

// On a 12^3 box of unit cells (6 Kuhn tets each): two blocks far apart give two small balls; a
// ring two cells thick around a 5-cell hole gives one ball that leaves the top and bottom layers
// out (the hole closed by the extra rings), a hollow cube around a 4-cell cavity one small ball
// with the cavity filled; a ring one cell thick around a 9-cell hole
// keeps its tunnel, so no local region is returned (the remesher then takes the whole mesh).
TEST(RemeshRegion, PiecesTunnelsAndCavitiesGiveLocalBalls) {
  const TetMesh box = structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(12.0), 12, 12, 12);
  const long all = box.num_tets();
  const auto in = [](int a, int lo, int hi) { return a >= lo && a <= hi; };

  const auto blocks = cells(box, [&](int i, int j, int k) {
    return (in(i, 1, 2) && in(j, 1, 2) && in(k, 1, 2)) || (in(i, 8, 9) && in(j, 8, 9) && in(k, 8, 9));
  });
  const auto two = band_regions(box, blocks);
  ASSERT_EQ(two.size(), 2u);
  for (const auto& region : two) {
    EXPECT_TRUE(region_is_ball(box, region));
    EXPECT_LT(count(region), all / 10);
  }
  EXPECT_TRUE(covers_disjointly(box, blocks, two));

  const auto ring = cells(box, [&](int i, int j, int k) {
    return in(k, 5, 6) && in(i, 2, 10) && in(j, 2, 10) && !(in(i, 4, 8) && in(j, 4, 8));
  });
  const auto closed = band_regions(box, ring);
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_TRUE(region_is_ball(box, closed[0]));
  const auto far_layers = cells(box, [&](int, int, int k) { return k == 0 || k == 11; });
  for (int t = 0; t < box.num_tets(); ++t)
    if (far_layers[t]) {
      EXPECT_FALSE(closed[0][t]) << "tet " << t << " in the bottom or top layer";
    }
  EXPECT_TRUE(covers_disjointly(box, ring, closed));

  const auto shell = cells(box, [&](int i, int j, int k) {
    return in(i, 3, 8) && in(j, 3, 8) && in(k, 3, 8) && !(in(i, 4, 7) && in(j, 4, 7) && in(k, 4, 7));
  });
  const auto filled = band_regions(box, shell);
  ASSERT_EQ(filled.size(), 1u);
  EXPECT_TRUE(region_is_ball(box, filled[0]));
  EXPECT_LT(count(filled[0]), all / 2);
  const auto centre = cells(box, [&](int i, int j, int k) { return in(i, 5, 6) && in(j, 5, 6) && in(k, 5, 6); });
  for (int t = 0; t < box.num_tets(); ++t)
    if (centre[t]) {
      EXPECT_TRUE(filled[0][t]) << "cavity tet " << t << " left out";
    }

  const auto wide_ring = cells(box, [&](int i, int j, int k) {
    return in(k, 5, 5) && in(i, 1, 11) && in(j, 1, 11) && !(in(i, 2, 10) && in(j, 2, 10));
  });
  EXPECT_TRUE(band_regions(box, wide_ring).empty());
}

// A refit in two opposite corners of an 8^3 Kuhn box (the sizing field moved there only, as when a
// liquid surface moves in two places) stays local: two triangulations, every tet at the centre
// kept, the box filled to round-off, no flat or inverted tet, the corners refined.
TEST(Remesher, RefitInTwoPlacesStaysLocal) {
  const TetMesh box = structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 8, 8, 8);
  RemeshOptions options;
  options.target_edge_length = mean_edge_length(box, kFluidSubdomain);
  const auto corner = [](const Eigen::Vector3d& x) { return x.sum() < 0.4 || x.sum() > 2.6; };
  options.size_at = [&](const Eigen::Vector3d& x) { return corner(x) ? 0.06 : 1.0; };
  const double h = options.target_edge_length;
  options.remesh_tets = resized_tets(
      box, [h](const Eigen::Vector3d&) { return h; },
      [&](const Eigen::Vector3d& x) { return std::min(h, options.size_at(x)); }, 1.3, 1);
  const RemeshResult r = remesh_step(box, box.vertices, options);
  EXPECT_TRUE(r.report.local) << r.report.summary();
  EXPECT_LT(r.report.region_tets, box.num_tets() * 3 / 4);
  EXPECT_NEAR(total_volume(r.mesh), 1.0, 1e-12);
  const QualityReport q = quality_report(r.mesh);
  EXPECT_EQ(q.inverted + q.degenerate, 0);
  EXPECT_GT(r.mesh.num_vertices(), box.num_vertices());  // the corners were refined
  std::vector<char> kept_vertex(box.num_vertices(), 0);
  for (int v : r.old_index)
    if (v >= 0) kept_vertex[v] = 1;
  for (int v = 0; v < box.num_vertices(); ++v)
    if (std::abs(box.vertices[v].sum() - 1.5) < 0.5) {
      EXPECT_TRUE(kept_vertex[v]) << "centre vertex " << v << " removed";
    }
}
