// Redistancing by closest-triangle propagation (fluid/liquid/zero_set_distance.hpp) against the
// exhaustive minimum over every triangle of the zero set, on a jittered mesh: a sphere given by a
// function that is not a distance, two spheres an edge apart (their medial plane, where a
// neighbour's nearest triangle need not be a node's own), and a tilted plane that ends on the walls
// (open edges, whose strips count). The zero set's own error is O(h^2 / R) (P1 interpolation of a
// surface of radius R): 0.2 h for R = 0.2 at h = 1/20. Within 2 h of the surface, where phi moves
// the surface over the next steps, propagation must stay an order of magnitude below that (0.01 h).
// Deeper, phi only sizes the mesh, and near a sphere's centre (where every direction is nearly as
// near, the distance has a kink and its P1 interpolant is off by O(h)) it may miss the nearest
// triangle by an order below that (0.1 h). It must be exact (to round-off) at 99% of the band.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "fluid/liquid/level_set.hpp"
#include "fluid/liquid/zero_set_distance.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

using Shape = std::function<double(const Eigen::Vector3d&)>;

struct Agreement {
  double max_error;     ///< largest |propagated - exhaustive| [m]
  double max_near_error;  ///< the same within 2 h of the surface [m]
  double exact_share;   ///< share of band nodes where they agree to 1e-12 m
  int band_nodes;       ///< nodes nearer the surface than the band
};

Agreement compare(const Shape& shape) {
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  const int n = 20;
  const double h = 1.0 / n, band = 4 * h;
  std::mt19937 rng(5);
  const FluidMesh mesh = build_fluid_mesh(testing::jittered(mesh::structured_box(lo, hi, n, n, n), lo, hi, h, 0.2, rng));
  const Eigen::VectorXd sampled = sample_level_set(mesh, shape);
  Eigen::VectorXd phi = sampled;
  redistance(mesh, phi, band);
  const mesh::SurfaceMesh zero = zero_set(mesh, sampled);
  const ZeroSetDistance distance(zero);
  Agreement a{0.0, 0.0, 0.0, 0};
  int exact = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    // redistance keeps +-band where the sampled function is already that far (level_set.hpp)
    double d = band;
    if (std::abs(sampled[i]) < band)
      for (int t = 0; t < zero.num_triangles(); ++t) d = std::min(d, distance(t, mesh.nodes[i]));
    const double error = std::abs(std::abs(phi[i]) - d);
    a.max_error = std::max(a.max_error, error);
    if (d < 2 * h) a.max_near_error = std::max(a.max_near_error, error);
    EXPECT_EQ(phi[i] < 0.0, sampled[i] < 0.0) << "node " << i << " changed side";
    if (d < band) {
      ++a.band_nodes;
      exact += error <= 1e-12;
    }
  }
  a.exact_share = double(exact) / std::max(1, a.band_nodes);
  return a;
}

void expect_agreement(const Shape& shape, const char* name) {
  const double h = 1.0 / 20;
  const Agreement a = compare(shape);
  std::printf("%s: %d band nodes, exact at %.2f%%, largest difference %.3g h (%.3g h within 2 h)\n", name,
              a.band_nodes, 100 * a.exact_share, a.max_error / h, a.max_near_error / h);
  EXPECT_GT(a.band_nodes, 500) << name;
  EXPECT_LE(a.max_near_error, 0.01 * h) << name;
  EXPECT_LE(a.max_error, 0.1 * h) << name;
  EXPECT_GE(a.exact_share, 0.99) << name;
}

TEST(ZeroSetDistance, PropagationFindsTheNearestTriangleOfASphere) {
  expect_agreement([](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(0.5, 0.45, 0.52)).squaredNorm() - 0.09; },
                   "sphere (|x - c|^2 - R^2)");
}

TEST(ZeroSetDistance, PropagationFindsTheNearestOfTwoSpheresAnEdgeApart) {
  expect_agreement(
      [](const Eigen::Vector3d& x) {
        return std::min((x - Eigen::Vector3d(0.27, 0.5, 0.5)).norm() - 0.2, (x - Eigen::Vector3d(0.73, 0.5, 0.5)).norm() - 0.2);
      },
      "two spheres 0.06 m apart");
}

TEST(ZeroSetDistance, PropagationCarriesTheStripsOfASurfaceEndingOnTheWalls) {
  expect_agreement([](const Eigen::Vector3d& x) { return x.z() - 0.41 - 0.2 * x.x() - 0.1 * x.y(); }, "tilted plane");
}

}  // namespace
}  // namespace tetfsi::fluid
