// The fast path (schur_cg with BoomerAMG, the default with the amg fluid solver) on a 3D coupled
// step: a soft block in a box of water (block_fixture.hpp). It must agree with the direct
// reference (UMFPACK) step after step, also once it solves with the lagged factor and AMG of the
// first step (steps 2 and 3),
// and must throw, not fall back, when its iteration cap is too small.
#include <gtest/gtest.h>

#include "apps/fixtures/block_fixture.hpp"

using namespace tetfsi;

namespace {

struct StepState {
  Eigen::VectorXd solid_velocity, pressure;
  std::string solver;
};

std::vector<StepState> run(coupling::CoupledSolverKind kind, int steps) {
  coupling::CoupledSolverOptions options;
  options.tolerance = 1e-10;
  auto scene = test::make_block_scene(test::block_in_box(12), kind, options);
  std::vector<StepState> states;
  for (int k = 0; k < steps; ++k) {
    const auto rep = scene->step(test::kBlockTimeStep);
    EXPECT_LE(rep.solve.residual.max(), 1e-10) << rep.solve.solver;
    states.push_back({scene->solid(0).velocity(), scene->fluid().pressure(), rep.solve.solver});
  }
  return states;
}

}  // namespace

TEST(CoupledBlock, FastPathAgreesWithUmfpackStepAfterStep) {
  const auto fast = run(coupling::CoupledSolverKind::SchurCG, 3);
  const auto reference = run(coupling::CoupledSolverKind::Umfpack, 3);
  EXPECT_EQ(fast[0].solver, "schur_cg+boomeramg");
  EXPECT_EQ(fast[1].solver, "block_gmres+boomeramg");  // the factor and AMG of step 1, lagged
  EXPECT_EQ(reference[0].solver, "umfpack");
  for (std::size_t k = 0; k < fast.size(); ++k) {
    // Both solves meet relative block residuals of 1e-10 (measured differences: ~1e-11).
    const double du = (fast[k].solid_velocity - reference[k].solid_velocity).norm() / reference[k].solid_velocity.norm();
    const double dp = (fast[k].pressure - reference[k].pressure).norm() / reference[k].pressure.norm();
    EXPECT_LT(du, 1e-9) << "step " << k + 1;
    EXPECT_LT(dp, 1e-9) << "step " << k + 1;
    EXPECT_GT(reference[k].solid_velocity.norm(), 1e-3);  // the block moves: not a trivial solve
  }
}

TEST(CoupledBlock, FastPathThrowsWhenTheIterationCapIsTooSmall) {
  coupling::CoupledSolverOptions options;
  options.tolerance = 1e-10;
  options.max_iterations = 3;
  auto scene = test::make_block_scene(test::block_in_box(12), coupling::CoupledSolverKind::SchurCG, options);
  EXPECT_THROW(scene->step(test::kBlockTimeStep), coupling::CoupledSolveError);
}
