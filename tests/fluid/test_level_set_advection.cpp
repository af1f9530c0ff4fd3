// Thin liquid features under the level set's advection (fluid/advection/nodal_advection.cpp): a
// drop of radius 3 h and a sheet 2 h thick carried by a uniform velocity across 16 cells in 32
// steps, on two jittered meshes that alternate every step (as a remeshed run reads each step's
// level set on a new mesh), redistanced every step as the solver does and without the volume
// restoration. The exact solution is the same shape, moved. First-order semi-Lagrangian
// interpolation loses the drop entirely and half the sheet; BFECC keeps clearly more (by 0.15 of
// the volume at least), though not all: a known gap (fluid/README.md, "Known gaps").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "fluid/advection/semi_lagrangian.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

struct Carried {
  double volume_ratio;  ///< liquid volume after / before
  double min_phi;       ///< deepest level-set value left (negative: the feature survives) [m]
};

using Sdf = std::function<double(const Eigen::Vector3d&)>;
using Advection = decltype(&advect_nodal);

Carried carry(const Sdf& shape, Advection advection) {
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 0.5, 0.5);
  const int n = 32;
  const double h = 1.0 / n;
  const mesh::TetMesh base = mesh::structured_box(lo, hi, n, n / 2, n / 2);
  std::mt19937 rng(17);
  const FluidMesh meshes[2] = {build_fluid_mesh(testing::jittered(base, lo, hi, h, 0.1, rng)),
                               build_fluid_mesh(testing::jittered(base, lo, hi, h, 0.1, rng))};
  const Eigen::Vector3d u(1.0, 0.0, 0.0);
  const double dt = 0.5 * h;
  const int steps = 32;  // 16 cells
  Eigen::VectorXd phi = sample_level_set(meshes[0], shape);
  const double band = 4 * h;
  redistance(meshes[0], phi, band);
  const double v0 = liquid_volume(meshes[0], phi);
  for (int s = 0; s < steps; ++s) {
    const FluidMesh& from = meshes[s % 2];
    const FluidMesh& to = meshes[(s + 1) % 2];
    const TetVectors velocity(from.num_tets(), u);
    phi = advection(from, velocity, phi, to, dt, nullptr, nullptr, nullptr);
    redistance(to, phi, band, true);  // the steps keep the cut tets (FluidSolver::update_liquid)
  }
  return {liquid_volume(meshes[steps % 2], phi) / v0, phi.minCoeff()};
}

TEST(LevelSetAdvection, BfeccKeepsAThinDropAndSheetThatFirstOrderFlattens) {
  const double h = 1.0 / 32;
  const Sdf drop = [h](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(0.25, 0.25, 0.25)).norm() - 3 * h; };
  const Sdf sheet = [h](const Eigen::Vector3d& x) { return std::abs(x.x() + x.y() - 0.5) / std::sqrt(2.0) - h; };
  struct Case {
    const char* name;
    Sdf shape;
  };
  for (const Case& c : {Case{"drop r = 3 h", drop}, Case{"sheet 2 h", sheet}}) {
    const Carried first = carry(c.shape, &advect_nodal);
    const Carried bfecc = carry(c.shape, &advect_nodal_bfecc);
    std::printf("%s carried 16 cells: volume kept %.3f (first order) / %.3f (BFECC); deepest phi %.3f h / %.3f h\n",
                c.name, first.volume_ratio, bfecc.volume_ratio, first.min_phi / h, bfecc.min_phi / h);
    // Measured: drop 0.000 / 0.915, sheet 0.518 / 0.668 (neither keeps its volume: see the file doc).
    EXPECT_GT(bfecc.volume_ratio, first.volume_ratio + 0.15) << c.name;
    EXPECT_LT(bfecc.volume_ratio, 1.0) << c.name;
  }
}

}  // namespace
}  // namespace tetfsi::fluid
