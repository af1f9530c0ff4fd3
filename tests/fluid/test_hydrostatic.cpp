// Still water stays still on a mesh that changes every step (p = p₀ + ρ g (H − z), v = 0): closed box,
// gravity, zero initial velocity, interior vertices re-jittered every step and the state advected
// from the previous mesh. In P1 the hydrostatic pressure rho g (H - z) is exact, so the projection
// cancels gravity to solver tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fluid/fluid_solver.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

TEST(FluidHydrostatic, StillWaterStaysStillOnAJitteredMesh) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.6, 0.4, 1.0);
  const int nx = 6, ny = 4, nz = 10;  // cubic cells of 0.1 m, 1440 tets
  const double h = 0.1, H = hi.z(), g = 9.81, rho = 1000.0, dt = 0.01;
  const mesh::TetMesh base = mesh::structured_box(lo, hi, nx, ny, nz);
  std::mt19937 rng(42);
  FluidParams params;
  params.density = rho;
  params.gravity = Eigen::Vector3d(0, 0, -g);
  FluidSolver solver(params);
  solver.initialize(testing::jittered(base, lo, hi, h, 0.1, rng));
  const double u_scale = std::sqrt(g * H);
  double worst_u = 0.0, worst_p = 0.0, worst_div = 0.0;
  for (int step = 0; step < 100; ++step) {
    const mesh::TetMesh m = testing::jittered(base, lo, hi, h, 0.1, rng);
    const StepReport r = solver.step(m, {}, dt);
    worst_div = std::max(worst_div, r.max_divergence);
    ASSERT_LE(r.max_divergence, 1e-8 * u_scale / h) << "step " << step;
    // The pressure matrix of this mesh: symmetric, positive diagonal (CG converged above).
    const Eigen::SparseMatrix<double> l = assemble_laplacian(solver.mesh());
    ASSERT_LE((l - Eigen::SparseMatrix<double>(l.transpose())).norm(), 1e-14 * l.norm());
    ASSERT_GT(l.diagonal().minCoeff(), 0.0);
    for (const auto& u : solver.fields().velocity) worst_u = std::max(worst_u, u.norm());
    ASSERT_LE(worst_u, 1e-8 * u_scale) << "step " << step;
    // Pressure relative to the top: rho g depth.
    const FluidMesh& fm = solver.mesh();
    double p_top = 0.0;
    int n_top = 0;
    for (int i = 0; i < fm.num_nodes(); ++i)
      if (std::abs(fm.nodes[i].z() - H) < 1e-12) {
        p_top += solver.pressure()[i];
        ++n_top;
      }
    p_top /= n_top;
    for (int i = 0; i < fm.num_nodes(); ++i) {
      const double depth = H - fm.nodes[i].z();
      worst_p = std::max(worst_p, std::abs(solver.pressure()[i] - p_top - rho * g * depth) / (rho * g * H));
    }
    ASSERT_LE(worst_p, 0.01) << "step " << step;
  }
  std::printf("hydrostatic, 100 jittered steps: max|u| / sqrt(gH) = %.3e, max |p - rho g depth| / (rho g H) = %.3e, "
              "max|div| h / sqrt(gH) = %.3e\n",
              worst_u / u_scale, worst_p, worst_div * h / u_scale);
}

}  // namespace
}  // namespace tetfsi::fluid
