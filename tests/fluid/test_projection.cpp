// Projection: weak divergence zero to solver tolerance, energy never increases, exact uniform flow
// between an inflow and an open boundary, closed-domain null space, both solver back ends.
#include <gtest/gtest.h>

#include <random>

#include "fluid/boundary/boundary_conditions.hpp"
#include "fluid/projection/projection.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

const Eigen::Vector3d kLo(0, 0, 0), kHi(1, 1, 1);
constexpr int kN = 8;
constexpr double kH = 1.0 / kN;

FluidMesh jittered_box(unsigned seed) {
  std::mt19937 rng(seed);
  return build_fluid_mesh(testing::jittered(mesh::structured_box(kLo, kHi, kN, kN, kN), kLo, kHi, kH, 0.1, rng));
}

TetVectors random_velocity(const FluidMesh& m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  TetVectors u(m.num_tets());
  for (auto& v : u) v = Eigen::Vector3d(d(rng), d(rng), d(rng));
  return u;
}

class ProjectionBackends : public ::testing::TestWithParam<SolverBackend> {};

TEST_P(ProjectionBackends, ClosedBoxRandomFieldBecomesDivergenceFree) {
  const FluidMesh m = jittered_box(11);
  const ClassifiedBoundary bc = classify_boundary(m, {});
  ASSERT_TRUE(bc.closed);
  TetVectors u = random_velocity(m, 12);
  const double e0 = kinetic_energy(m, u);
  SolverOptions opt;
  opt.backend = GetParam();
  opt.tolerance = 1e-12;
  const ProjectionReport r = project(m, bc, 0.01, 1000.0, u, opt);
  const double velocity_scale = 1.0;
  EXPECT_LE(r.max_divergence, 1e-8 * velocity_scale / kH);
  EXPECT_LE(r.solve.relative_residual, 1e-11);
  EXPECT_GT(r.solve.iterations, 0);
  // V-orthogonal projection: energy does not grow, and a second projection changes nothing.
  const double e1 = kinetic_energy(m, u);
  EXPECT_LT(e1, e0);
  const TetVectors u1 = u;
  const ProjectionReport r2 = project(m, bc, 0.01, 1000.0, u, opt);
  double change = 0.0;
  for (int t = 0; t < m.num_tets(); ++t) change = std::max(change, (u[t] - u1[t]).norm());
  EXPECT_LE(change, 1e-9);
  EXPECT_LE(r2.max_divergence, 1e-8 / kH);
  // Pythagoras of an orthogonal projection: |u0|^2 = |Pu0|^2 + |u0 - Pu0|^2 in the V-norm.
  const TetVectors u0 = random_velocity(m, 12);
  double cross = 0.0;
  for (int t = 0; t < m.num_tets(); ++t) cross += m.volume[t] * (u0[t] - u[t]).dot(u[t]);
  EXPECT_LE(std::abs(cross), 1e-9 * e0);
}

TEST_P(ProjectionBackends, InflowToOpenBoundaryGivesExactUniformFlow) {
  const FluidMesh m = jittered_box(13);
  BoundaryConditions bcs;
  const double U = 2.0;
  BoundaryPatch in;
  in.region = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 1)};
  in.kind = FaceKind::kInflow;
  in.velocity = Eigen::Vector3d(U, 0, 0);
  BoundaryPatch out;
  out.region = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 1)};
  out.kind = FaceKind::kOpen;
  bcs.patches = {in, out};
  const ClassifiedBoundary bc = classify_boundary(m, bcs);
  ASSERT_FALSE(bc.closed);
  TetVectors u(m.num_tets(), Eigen::Vector3d::Zero());
  SolverOptions opt;
  opt.backend = GetParam();
  opt.tolerance = 1e-12;
  const double dt = 0.05, rho = 1.2;
  const ProjectionReport r = project(m, bc, dt, rho, u, opt);
  for (int t = 0; t < m.num_tets(); ++t) ASSERT_LE((u[t] - Eigen::Vector3d(U, 0, 0)).norm(), 1e-8 * U) << t;
  // p = (rho U / dt)(1 - x): the impulse that starts the flow, linear so exact in P1.
  for (int i = 0; i < m.num_nodes(); ++i)
    ASSERT_NEAR(r.pressure[i], rho * U / dt * (1.0 - m.nodes[i].x()), 1e-8 * rho * U / dt);
  EXPECT_LE(r.max_divergence, 1e-8 * U / kH);
}

INSTANTIATE_TEST_SUITE_P(Solvers, ProjectionBackends,
                         ::testing::Values(SolverBackend::kHypreAmgCg, SolverBackend::kEigenIcCg,
                                           SolverBackend::kPetscAmgCg),
                         [](const ::testing::TestParamInfo<SolverBackend>& info) {
                           return info.param == SolverBackend::kHypreAmgCg  ? std::string("hypre")
                                  : info.param == SolverBackend::kEigenIcCg ? std::string("eigen_ic")
                                                                            : std::string("petsc");
                         });

TEST(Projection, ClosedDomainWithNetInflowIsAnError) {
  const FluidMesh m = jittered_box(14);
  BoundaryConditions bcs;
  BoundaryPatch in;
  in.region = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 1)};
  in.kind = FaceKind::kInflow;
  in.velocity = Eigen::Vector3d(1, 0, 0);
  bcs.patches = {in};
  const ClassifiedBoundary bc = classify_boundary(m, bcs);
  TetVectors u(m.num_tets(), Eigen::Vector3d::Zero());
  EXPECT_THROW(project(m, bc, 0.1, 1.0, u, {}), std::invalid_argument);
}

TEST(Projection, NonConvergenceIsReported) {
  const FluidMesh m = jittered_box(15);
  const ClassifiedBoundary bc = classify_boundary(m, {});
  TetVectors u = random_velocity(m, 16);
  for (SolverBackend b : {SolverBackend::kHypreAmgCg, SolverBackend::kEigenIcCg, SolverBackend::kPetscAmgCg}) {
    SolverOptions opt;
    opt.backend = b;
    opt.tolerance = 1e-14;
    opt.max_iterations = 1;
    TetVectors v = u;
    EXPECT_THROW(project(m, bc, 0.1, 1.0, v, opt), SolverError) << to_string(b);
    try {  // the message shows the tolerance (std::to_string printed it as 0.000000)
      project(m, bc, 0.1, 1.0, v, opt);
    } catch (const SolverError& e) {
      EXPECT_NE(std::string(e.what()).find("tolerance 1e-14"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_solver_backend("lu"), std::invalid_argument);
}

}  // namespace
}  // namespace tetfsi::fluid
