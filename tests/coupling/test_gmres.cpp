// The hand-written restarted GMRES of the fast path's lagged solves (coupling/solvers/gmres.hpp)
// against a dense LU, on an unsymmetric convection-diffusion matrix, with and without restarts,
// with a right preconditioner, and honest about a missed cap.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "coupling/solvers/gmres.hpp"

using tetfsi::coupling::detail::right_preconditioned_gmres;

namespace {

// 1D upwind convection-diffusion, -u'' + c u' on n interior nodes: unsymmetric, nonsingular.
Eigen::MatrixXd convection_diffusion(int n, double peclet) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    K(i, i) = 2.0 + peclet;
    if (i > 0) K(i, i - 1) = -1.0 - peclet;
    if (i + 1 < n) K(i, i + 1) = -1.0;
  }
  return K;
}

}  // namespace

TEST(Gmres, MatchesDenseLUWithAndWithoutRestartsAndPreconditioner) {
  const int n = 60;
  const Eigen::MatrixXd K = convection_diffusion(n, 0.8);
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(n, 1.0, -2.0);
  const Eigen::VectorXd ref = K.partialPivLu().solve(f);
  auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y = K * v; };
  auto identity = [](const Eigen::VectorXd& v, Eigen::VectorXd& z) { z = v; };
  const Eigen::VectorXd diag = K.diagonal();
  auto jacobi = [&](const Eigen::VectorXd& v, Eigen::VectorXd& z) { z = v.cwiseQuotient(diag); };
  const double target = 1e-10 * f.norm();
  for (int restart : {n, 10}) {
    for (bool preconditioned : {false, true}) {
      Eigen::VectorXd x;
      const auto r = preconditioned ? right_preconditioned_gmres(apply, jacobi, f, x, target, 2000, restart)
                                    : right_preconditioned_gmres(apply, identity, f, x, target, 2000, restart);
      EXPECT_TRUE(r.converged) << restart << " " << preconditioned;
      EXPECT_LE((f - K * x).norm(), target) << restart << " " << preconditioned;  // the true residual
      EXPECT_NEAR(r.residual, (f - K * x).norm(), 1e-12 * f.norm());
      // cond(K) is ~1e3 here, so a 1e-10 residual bounds the error near 1e-7.
      EXPECT_LT((x - ref).norm(), 1e-6 * ref.norm()) << restart << " " << preconditioned;
      if (restart == n) {
        EXPECT_LE(r.iterations, n);  // full GMRES terminates in at most n steps
      }
    }
  }
}

TEST(Gmres, ReportsAMissedCapWithItsTrueResidual) {
  const int n = 60;
  const Eigen::MatrixXd K = convection_diffusion(n, 0.8);
  const Eigen::VectorXd f = Eigen::VectorXd::Ones(n);
  auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y = K * v; };
  auto identity = [](const Eigen::VectorXd& v, Eigen::VectorXd& z) { z = v; };
  Eigen::VectorXd x;
  const auto r = right_preconditioned_gmres(apply, identity, f, x, 1e-12, 5, 40);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 5);
  EXPECT_NEAR(r.residual, (f - K * x).norm(), 1e-12);
  EXPECT_LT(r.residual, f.norm());  // but it did reduce the residual
}

TEST(Gmres, StopsAtBreakdownAndNeverReturnsAWorseIterate) {
  // K = 3I: the first Krylov step already spans the solution (breakdown); with a target of 0
  // GMRES must stop near round-off instead of iterating on rounding noise.
  const int n = 20;
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  auto identity = [](const Eigen::VectorXd& v, Eigen::VectorXd& z) { z = v; };
  auto three = [](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y = 3.0 * v; };
  Eigen::VectorXd x;
  auto r = right_preconditioned_gmres(three, identity, f, x, 0.0, 100, 40);
  EXPECT_LE(r.iterations, 5);
  EXPECT_LE((f - 3.0 * x).norm(), 1e-15 * f.norm());
  EXPECT_DOUBLE_EQ(r.residual, (f - 3.0 * x).norm());
  // Singular K = diag(1, ..., 1, 0) with f not in its range: the residual cannot fall below
  // |f_n| = 2; GMRES must end with it there, not grow it.
  auto singular = [n](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    y = v;
    y[n - 1] = 0.0;
  };
  x.resize(0);
  r = right_preconditioned_gmres(singular, identity, f, x, 0.0, 100, 40);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(x.allFinite());
  EXPECT_NEAR(r.residual, 2.0, 1e-12);
  Eigen::VectorXd Kx;
  singular(x, Kx);
  EXPECT_NEAR((f - Kx).norm(), r.residual, 1e-12);
}

TEST(Gmres, APreconditionerRoundedToSinglePrecisionCostsNoExtraIterations) {
  // Flexible GMRES keeps zⱼ = M⁻¹vⱼ and updates x with them, so a preconditioner whose output is
  // rounded to float (a factor kept in single precision) reaches a residual far below float's
  // rounding in the iterations the exact one takes (give or take one). Applying M⁻¹ once more to a
  // combination of the vⱼ (Saad's Alg. 9.5) would leave that rounding, ~1e-7, in the residual
  // and need another cycle.
  const int n = 80;
  const Eigen::MatrixXd K = convection_diffusion(n, 0.5);
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(n, 2.0, -1.0);
  auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y = K * v; };
  const Eigen::VectorXd diag = K.diagonal();
  auto jacobi = [&](const Eigen::VectorXd& v, Eigen::VectorXd& z) { z = v.cwiseQuotient(diag); };
  auto rounded = [&](const Eigen::VectorXd& v, Eigen::VectorXd& z) {
    z = v.cwiseQuotient(diag).cast<float>().cast<double>();
  };
  const double target = 1e-12 * f.norm();
  Eigen::VectorXd x_exact, x_rounded;
  const auto exact = right_preconditioned_gmres(apply, jacobi, f, x_exact, target, 2000, n);
  const auto single = right_preconditioned_gmres(apply, rounded, f, x_rounded, target, 2000, n);
  ASSERT_TRUE(exact.converged);
  ASSERT_TRUE(single.converged);
  EXPECT_LE((f - K * x_rounded).norm(), target);
  EXPECT_LE(single.iterations, exact.iterations + 1) << "exact " << exact.iterations << ", rounded " << single.iterations;
}
