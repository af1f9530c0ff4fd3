// The smooth liquid surface for renderers (fluid/io/render_surface.hpp) on jittered Kuhn meshes:
// - a still pool (phi = y - H, the level set the solver keeps for still water) gives a closed,
//   outward surface whose top is flat to 1% of the tet edge length, at the still height, ending on
//   the walls, enclosing the pool's volume;
// - the vertex velocities are the node-averaged velocity interpolated linearly (a linear field is
//   reproduced exactly);
// - voxel sampling, the smoothing's box passes and the mean edge of the cut tets (helpers).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "fluid/io/level_set_voxels.hpp"
#include "fluid/io/render_surface.hpp"
#include "fluid/io/surface_voxels.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid_test_support.hpp"
#include "mesh/quality.hpp"
#include "tests/fluid/surface_checks.hpp"

namespace tetfsi::fluid {
namespace {

/// The fluid mesh of a jittered Kuhn box [lo, hi] with cells of edge h.
FluidMesh jittered_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double h, unsigned seed) {
  const Eigen::Vector3i n = ((hi - lo) / h).array().round().cast<int>();
  std::mt19937 rng(seed);
  const mesh::TetMesh m = testing::jittered(mesh::structured_box(lo, hi, n.x(), n.y(), n.z()), lo, hi, h, 0.1, rng);
  return build_fluid_mesh(m);
}

TEST(RenderSurface, StillPoolIsFlatToOnePercentOfTheEdgeAndEndsOnTheWalls) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.6, 0.4, 0.3);
  const double h = 0.05, H = 0.17;
  const FluidMesh mesh = jittered_box(lo, hi, h, 5);
  const Eigen::VectorXd phi = sample_level_set(mesh, [&](const Eigen::Vector3d& x) { return x.y() - H; });
  const double edge = cut_tet_edge_length(mesh, phi, 0.1);
  // Kuhn tets: three edges h, two sqrt2 h, one sqrt3 h (mean 1.26 h), jittered by up to 0.1 h.
  EXPECT_NEAR(edge, 1.26 * h, 0.15 * h);
  EXPECT_LE(cut_tet_edge_length(mesh, phi, 0.0), edge);
  EXPECT_GE(cut_tet_edge_length(mesh, phi, 1.0), edge);
  // The run's defaults (apps/run/output.hpp: voxels of a quarter of the smoothing, which is then
  // made on voxels of half of it), and one resolution for both (voxels of half the smoothing).
  for (const double voxels_per_sigma : {4.0, 2.0}) {
    SCOPED_TRACE(voxels_per_sigma);
    RenderSurfaceOptions options;
    options.smoothing = edge;
    options.voxel_size = edge / voxels_per_sigma;
    const RenderSurface s = render_surface(mesh, phi, TetVectors(mesh.num_tets(), Eigen::Vector3d::Zero()), options);
    ASSERT_GT(s.surface.num_triangles(), 0);
    EXPECT_EQ(testing::open_or_nonmanifold_edges(s.surface), 0);
    const double pool = 0.6 * H * 0.3;
    EXPECT_NEAR(s.liquid_volume, pool, 1e-12);
    EXPECT_NEAR(s.enclosed_volume, testing::enclosed_volume(s.surface), 1e-12);
    EXPECT_NEAR(s.enclosed_volume, pool, 1e-4 * pool);  // the iso shift's tolerance
    // The top: every vertex of a triangle facing up, crease vertices on the walls included.
    double worst = 0, top_area = 0;
    for (const auto& t : s.surface.triangles) {
      const Eigen::Vector3d n = testing::normal(s.surface, t);
      if (n.y() < 0.5) continue;
      top_area += testing::area(s.surface, t);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(s.surface.vertices[t[k]].y() - H));
    }
    std::printf("still pool, voxel = smoothing / %g: %d triangles, top flat to %.3g of the edge (%.3g m), volume "
                "%+.2e, iso shift %.3g m\n",
                voxels_per_sigma, s.surface.num_triangles(), worst / edge, worst, s.enclosed_volume / pool - 1,
                s.iso_shift);
    EXPECT_LT(worst, 0.01 * edge);
    EXPECT_NEAR(top_area, 0.6 * 0.3, 1e-6);  // the top spans the tank: it ends on the walls
    for (const auto& x : s.surface.vertices) {  // nothing beyond the walls (float coordinates)
      EXPECT_TRUE(((x - lo).array() > -1e-6).all() && ((hi - x).array() > -1e-6).all()) << x.transpose();
    }
  }
}

TEST(RenderSurface, VertexVelocityIsTheNodeFieldInterpolated) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.4, 0.4, 0.4);
  const FluidMesh mesh = jittered_box(lo, hi, 0.05, 9);
  const Eigen::VectorXd phi =
      sample_level_set(mesh, [](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(0.2, 0.2, 0.2)).norm() - 0.12; });
  // A per-tet field whose node averages are linear: u_t = A x_t + b at the centroids averages to
  // A x_n + b at interior nodes only, so use a constant field (exact everywhere) and check the
  // interpolation against the node averages directly.
  TetVectors u(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) u[t] = Eigen::Vector3d(1.0, -2.0, 0.5) + 0.1 * mesh.centroid(t);
  RenderSurfaceOptions options;
  options.voxel_size = 0.025;
  options.smoothing = 0.05;
  const RenderSurface s = render_surface(mesh, phi, u, options);
  ASSERT_EQ(s.velocity.size(), s.surface.vertices.size());
  ASSERT_GT(s.velocity.size(), 100u);
  // Interior nodes average the centroids of their tets, so there the node value is A x_n + b to
  // O(jitter); the surface (radius 0.12 about the centre) lies in the interior.
  double worst = 0;
  for (std::size_t v = 0; v < s.velocity.size(); ++v)
    worst = std::max(worst, (s.velocity[v] - (Eigen::Vector3d(1.0, -2.0, 0.5) + 0.1 * s.surface.vertices[v])).norm());
  EXPECT_LT(worst, 0.1 * 0.05);  // 0.1 x (a fraction of an edge)
}

TEST(RenderSurface, SmoothingStepsMakeUpTheGaussianVariance) {
  // n steps of dt <= h^2 / 6 reach t = sigma^2 / 2 (variance sigma^2 per axis); the band holds 3 sigma.
  EXPECT_EQ(smoothing_steps(0), 0);
  EXPECT_EQ(smoothing_band_voxels(0), 2);
  for (double sigma : {0.3, 1.0, 2.0, 4.0}) {
    const int n = smoothing_steps(sigma);
    EXPECT_LE(0.5 * sigma * sigma / n, 1.0 / 6.0 + 1e-12) << sigma;
    EXPECT_GT(0.5 * sigma * sigma / (n - 1), 1.0 / 6.0 - 1e-12) << sigma;  // no more steps than needed
    EXPECT_GE(smoothing_band_voxels(sigma), 3 * sigma + 2) << sigma;
  }
}

TEST(RenderSurface, VoxelsOfTheLevelSetAreItsP1ValuesOnce) {
  const FluidMesh mesh = jittered_box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.3, 0.3), 0.05, 3);
  const Eigen::VectorXd phi = sample_level_set(mesh, [](const Eigen::Vector3d& x) { return x.x() + 2 * x.y() - 0.3; });
  const LevelSetVoxels v = sample_level_set_voxels(mesh, phi, 0.01, 0.1, liquid_tets(mesh, phi, 0.1));
  std::map<std::array<int, 3>, int> seen;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const Eigen::Vector3d x = v.index[k].cast<double>() * 0.01;
    const std::array<int, 3> key{v.index[k].x(), v.index[k].y(), v.index[k].z()};
    EXPECT_EQ(++seen[key], 1);
    EXPECT_NEAR(v.phi[k], std::clamp(x.x() + 2 * x.y() - 0.3, -0.1, 0.1), 1e-6);
  }
  // Every voxel centre of the box (31^3 of them) in the liquid is there.
  std::size_t liquid = 0, listed = 0;
  for (int i = 0; i <= 30; ++i)
    for (int j = 0; j <= 30; ++j)
      for (int k = 0; k <= 30; ++k) liquid += 0.01 * i + 0.02 * j - 0.3 < -1e-9;
  for (std::size_t k = 0; k < v.size(); ++k) listed += v.phi[k] < -1e-7;
  EXPECT_EQ(listed, liquid);
}

}  // namespace
}  // namespace tetfsi::fluid
