// parallel/: the row blocks of the processes, and PETSc's BoomerAMG-CG and V-cycle against the
// shared-memory hypre path on one process (the same settings, so the same iterations within one
// and the same solution to the tolerance). Several processes: tests/apps/test_mpi_run.cpp.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <vector>

#include "fluid/projection/amg_preconditioner.hpp"
#include "fluid/projection/linear_solver.hpp"
#include "parallel/distributed_solve.hpp"
#include "parallel/mpi_session.hpp"

using namespace tetfsi;

namespace {

/// The 7-point Laplacian of an n³ grid with a Dirichlet shift on the diagonal (SPD).
Eigen::SparseMatrix<double> laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int r = id(i, j, k);
        t.emplace_back(r, r, 6.0 + 1e-3);
        if (i > 0) t.emplace_back(r, id(i - 1, j, k), -1.0);
        if (i < n - 1) t.emplace_back(r, id(i + 1, j, k), -1.0);
        if (j > 0) t.emplace_back(r, id(i, j - 1, k), -1.0);
        if (j < n - 1) t.emplace_back(r, id(i, j + 1, k), -1.0);
        if (k > 0) t.emplace_back(r, id(i, j, k - 1), -1.0);
        if (k < n - 1) t.emplace_back(r, id(i, j, k + 1), -1.0);
      }
  Eigen::SparseMatrix<double> a(n * n * n, n * n * n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

}  // namespace

TEST(DistributedSolve, OwnedRowsCoverTheMatrixOnceInOrder) {
  for (int processes : {1, 2, 3, 7})
    for (int n : {0, 1, 5, 100, 101}) {
      int next = 0;
      for (int r = 0; r < processes; ++r) {
        const parallel::RowRange rows = parallel::owned_rows(n, r, processes);
        EXPECT_EQ(rows.begin, next);
        EXPECT_GE(rows.size(), n / processes);
        EXPECT_LE(rows.size(), n / processes + 1);
        next = rows.end;
      }
      EXPECT_EQ(next, n);
    }
}

TEST(DistributedSolve, PetscCgMatchesHypreOnOneProcess) {
  const Eigen::SparseMatrix<double> a = laplacian(24);
  Eigen::VectorXd b(a.rows());
  for (int i = 0; i < b.size(); ++i) b[i] = std::sin(0.37 * i) + 0.1;
  fluid::SolverOptions options;
  options.tolerance = 1e-10;
  Eigen::VectorXd x_hypre, x_petsc;
  const fluid::SolveReport hypre = fluid::solve_spd(a, b, x_hypre, options);
  options.backend = fluid::SolverBackend::kPetscAmgCg;
  const fluid::SolveReport petsc = fluid::solve_spd(a, b, x_petsc, options);
  EXPECT_EQ(parallel::num_processes(), 1);
  EXPECT_LE(petsc.relative_residual, 1e-10);
  EXPECT_NEAR(petsc.iterations, hypre.iterations, 1);
  EXPECT_LE((x_petsc - x_hypre).norm(), 1e-8 * x_hypre.norm());
}

TEST(DistributedSolve, VCycleIsTheSharedMemoryOne) {
  const Eigen::SparseMatrix<double> a = laplacian(16);
  Eigen::VectorXd r(a.rows()), z_hypre, z_petsc;
  for (int i = 0; i < r.size(); ++i) r[i] = std::cos(0.11 * i);
  fluid::AmgPreconditioner hypre;
  hypre.setup(a);
  hypre.apply(r, z_hypre);
  parallel::DistributedAmg petsc;
  EXPECT_THROW(petsc.apply(r, z_petsc), std::logic_error);
  petsc.setup(a);
  petsc.apply(r, z_petsc);
  // One V-cycle is a fixed linear map: the same settings give the same map up to round-off, and
  // it reduces the error of a ≈ r by the usual multigrid factor.
  EXPECT_LE((z_petsc - z_hypre).norm(), 1e-10 * z_hypre.norm());
  EXPECT_LT((r - a * z_petsc).norm(), 0.5 * r.norm());
}
