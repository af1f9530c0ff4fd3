// A still shallow layer keeps its volume without the volume restoration (tetfsi issue 15): liquid
// two cells deep at rest, gravity on, the fluid remeshed by CGAL before each of 200 steps, with
// LiquidOptions::restore_volume off, so that any volume the level set's transfer to the new mesh
// or its redistancing loses stays lost. Bound: 0.1% of the volume over the run, and the layer at
// rest (max|u| <= 1e-8 sqrt(g D) in the box, 1e-3 sqrt(g D) in the bowl).
//  - a box tank: the surface is a plane meeting vertical walls (phi linear; exact before too);
//  - a spherical tank (a bowl): the waterline lies on a wall that leans outward. Before the cut
//    tets kept their values in redistancing and the distance continued the surface across the
//    wall (level_set.hpp), the distance to the cut-off zero set grew towards the rim and the layer
//    lost 0.4-0.6% of its volume per step in redistancing and 0.01-0.1% in the transfer
//    (measured at edge 0.05 m; fluid/README.md); this run lost 56% of the layer and moved at
//    0.20 sqrt(g D).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "fluid/fluid_solver.hpp"
#include "fluid/liquid/level_set.hpp"
#include "fluid_test_support.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesher.hpp"

namespace tetfsi::fluid {
namespace {

struct LayerRun {
  double volume_error = 0;  ///< max |V - V0| / V0 over the steps
  double speed = 0;         ///< max |u| in the liquid / sqrt(g D)
  int new_vertices = 0;     ///< made by CGAL over the run
};

/// 200 steps of a layer with surface z = z_s, depth `depth`; `jitter` moves the interior vertices
/// of a structured box [lo, hi] before each remesh (CGAL keeps an already good mesh otherwise).
LayerRun still_layer(mesh::TetMesh m, double h, double z_s, double depth, bool jitter, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi) {
  const double g = 9.81, dt = 0.01;
  std::mt19937 rng(5);
  FluidParams params;
  params.density = 1000.0;
  params.gravity = Eigen::Vector3d(0, 0, -g);
  FluidSolver solver(params);
  solver.initialize(m);
  LiquidOptions liquid;
  liquid.band = 4 * h;
  liquid.restore_volume = false;
  solver.set_liquid(sample_level_set(solver.mesh(), [&](const Eigen::Vector3d& x) { return x.z() - z_s; }), liquid);
  const double v0 = solver.target_liquid_volume();
  mesh::RemeshOptions options;
  options.target_edge_length = h;
  options.iterations = 1;
  LayerRun out;
  for (int step = 0; step < 200; ++step) {
    mesh::TetMesh j = m;
    for (double amplitude = 0.05; jitter; amplitude *= 0.5) {
      j = testing::jittered(m, lo, hi, h, amplitude, rng);
      const mesh::QualityReport q = mesh::quality_report(j);
      if (q.inverted + q.degenerate == 0) break;
    }
    const mesh::RemeshResult r = mesh::remesh_step(j, j.vertices, options);
    for (int v : r.old_index) out.new_vertices += (v < 0);
    m = r.mesh;
    const StepReport s = solver.step(m, {}, dt);
    out.volume_error = std::max(out.volume_error, std::abs(s.liquid_volume - v0) / v0);
    for (int t = 0; t < solver.mesh().num_tets(); ++t)
      if (solver.liquid().liquid_volume[t] > 0)
        out.speed = std::max(out.speed, solver.fields().velocity[t].norm() / std::sqrt(g * depth));
  }
  return out;
}

/// Prints the run and checks it: volume within 0.1%, the liquid's speed within speed_bound sqrt(g D).
void expect_kept(const std::string& what, const LayerRun& r, double speed_bound) {
  std::printf("%s, layer 2 cells deep, 200 remeshed steps (%d vertices made by CGAL), no restoration: max volume "
              "error %.3e, max|u| / sqrt(gD) %.3e\n",
              what.c_str(), r.new_vertices, r.volume_error, r.speed);
  EXPECT_GT(r.new_vertices, 0) << what;
  EXPECT_LE(r.volume_error, 1e-3) << what;
  EXPECT_LE(r.speed, speed_bound) << what;
}

TEST(ShallowLayer, StillLayerTwoCellsDeepInABoxKeepsItsVolumeWhenRemeshedEveryStep) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.6, 0.45, 0.45);
  const double h = 0.15;
  expect_kept("box tank", still_layer(mesh::structured_box(lo, hi, 4, 3, 3), h, 2 * h, 2 * h, true, lo, hi), 1e-8);
}

TEST(ShallowLayer, StillLayerTwoCellsDeepInABowlKeepsItsVolumeWhenRemeshedEveryStep) {
  const double radius = 0.3, h = 0.1;
  mesh::MeshSizing sizing;
  sizing.edge_length = h;
  const mesh::TetMesh m = mesh::build_complex(mesh::make_sphere(radius, 2), {}, sizing, {});
  // 7.5e-5 measured: phi is linear but for the wedges at the corners of the waterline's polygon.
  expect_kept("spherical tank r = 0.3 m, edge 0.1 m (" + std::to_string(m.num_tets()) + " tets)",
              still_layer(m, h, -radius + 2 * h, 2 * h, false, {}, {}), 1e-3);
}

}  // namespace
}  // namespace tetfsi::fluid
