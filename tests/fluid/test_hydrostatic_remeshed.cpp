// Still water stays still when the mesh is remeshed every step (issue 5 acceptance;
// p = p₀ + ρ g (H − z), v = 0): closed box, gravity on, zero initial velocity; every step the interior vertices are
// jittered and mesh::remesh_step remeshes the fluid with CGAL (the remesh is forced: the jittered
// mesh is handed over as the new one, remesh_only_when_needed off), then the solver advects the
// state onto the new mesh and projects. In P1 the hydrostatic pressure rho g (H - z) is exact on
// any mesh, so velocity must stay at solver-tolerance level: |u| < 1e-8 sqrt(gH) for 100 steps and
// p - p_top = rho g depth within 1% of rho g H.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fluid/fluid_solver.hpp"
#include "fluid_test_support.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesher.hpp"

namespace tetfsi::fluid {
namespace {

TEST(FluidHydrostatic, StillWaterStaysStillWhenRemeshedEveryStep) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.45, 0.3, 0.75);
  const double h = 0.15, H = hi.z(), g = 9.81, rho = 1000.0, dt = 0.01;
  mesh::TetMesh m = mesh::structured_box(lo, hi, 3, 2, 5);
  std::mt19937 rng(7);
  FluidParams params;
  params.density = rho;
  params.gravity = Eigen::Vector3d(0, 0, -g);
  FluidSolver solver(params);
  solver.initialize(m);
  mesh::RemeshOptions options;
  options.target_edge_length = h;
  options.iterations = 1;
  const double u_scale = std::sqrt(g * H);
  double worst_u = 0.0, worst_p = 0.0, worst_div = 0.0, min_dihedral = 180.0;
  int new_vertices = 0;
  for (int step = 0; step < 100; ++step) {
    // Jitter (halving the amplitude until no tet inverts), then remesh.
    mesh::TetMesh j;
    for (double amplitude = 0.05;; amplitude *= 0.5) {
      j = testing::jittered(m, lo, hi, h, amplitude, rng);
      const mesh::QualityReport q = mesh::quality_report(j);
      if (q.inverted + q.degenerate == 0) break;
    }
    const mesh::RemeshResult r = mesh::remesh_step(j, j.vertices, options);
    ASSERT_TRUE(r.report.remeshed);
    ASSERT_EQ(mesh::quality_report(r.mesh).inverted, 0) << "step " << step;
    for (int v : r.old_index) new_vertices += (v < 0);
    min_dihedral = std::min(min_dihedral, r.report.min_dihedral_deg);
    m = r.mesh;

    const StepReport s = solver.step(m, {}, dt);
    worst_div = std::max(worst_div, s.max_divergence);
    ASSERT_LE(s.max_divergence, 1e-8 * u_scale / h) << "step " << step;
    for (const auto& u : solver.fields().velocity) worst_u = std::max(worst_u, u.norm());
    ASSERT_LE(worst_u, 1e-8 * u_scale) << "step " << step;
    const FluidMesh& fm = solver.mesh();
    double p_top = 0.0;
    int n_top = 0;
    for (int i = 0; i < fm.num_nodes(); ++i)
      if (std::abs(fm.nodes[i].z() - H) < 1e-12) {
        p_top += solver.pressure()[i];
        ++n_top;
      }
    ASSERT_GT(n_top, 0);
    p_top /= n_top;
    for (int i = 0; i < fm.num_nodes(); ++i) {
      const double depth = H - fm.nodes[i].z();
      worst_p = std::max(worst_p, std::abs(solver.pressure()[i] - p_top - rho * g * depth) / (rho * g * H));
    }
    ASSERT_LE(worst_p, 0.01) << "step " << step;
  }
  // The remesher really changed the mesh (CGAL made new vertices), not just moved it.
  EXPECT_GT(new_vertices, 0);
  std::printf("hydrostatic, 100 remeshed steps (%d tets at the end, %d vertices made by CGAL, fluid min dihedral "
              "%.1f deg): max|u| / sqrt(gH) = %.3e, max |p - rho g depth| / (rho g H) = %.3e, max|div| h / sqrt(gH) = "
              "%.3e\n",
              m.num_tets(), new_vertices, min_dihedral, worst_u / u_scale, worst_p, worst_div * h / u_scale);
}

}  // namespace
}  // namespace tetfsi::fluid
