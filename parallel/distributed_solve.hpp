#pragma once
/// @file distributed_solve.hpp
/// Symmetric positive definite solves on PETSc 3.18 over MPI, with hypre's BoomerAMG as PETSc's
/// preconditioner (PCHYPRE), for the pressure projection and the coupled solve when a scene sets
/// `fluid.solver.type` to `petsc`.
///
/// Every process passes the same whole matrix and right-hand side (tetfsi replicates its data,
/// mpi_session.hpp); each contributes only the rows it owns (owned_rows) to a MATMPIAIJ matrix,
/// PETSc and hypre solve with the rows spread over the processes, and the whole solution is
/// gathered back to every process. With one process this is the same algorithm as the
/// shared-memory hypre path (fluid/projection/linear_solver.hpp) with the same BoomerAMG settings,
/// so both give the same answer to the solver tolerance.
///
/// BoomerAMG settings (the shared-memory path's): HMIS coarsening, extended+i interpolation with
/// at most 4 elements per row, strong threshold 0.5, one level of aggressive coarsening, one
/// hybrid Gauss-Seidel sweep forward on the way down and backward on the way up (a symmetric
/// V-cycle, so CG may use it), Gaussian elimination on the coarsest level. Any of them can be
/// overridden at run time through $PETSC_OPTIONS with the prefix `tetfsi_` (e.g.
/// `PETSC_OPTIONS="-tetfsi_pc_hypre_boomeramg_strong_threshold 0.25"`).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <stdexcept>

namespace tetfsi::parallel {

/// A PETSc call failed, or the Krylov solve did not converge (the message says which).
struct PetscError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct DistributedSolveReport {
  int iterations = 0;
  double setup_seconds = 0;  ///< matrix distribution and the AMG hierarchy
  double solve_seconds = 0;  ///< CG iterations and the gather of the solution
};

/// Solves a x = b (a symmetric positive definite, both triangles stored, the same on every
/// process) by PETSc's CG (KSPCG) with one BoomerAMG V-cycle as preconditioner, stopping at
/// ||b − a x||₂ ≤ tolerance ||b||₂ (unpreconditioned residual). x is the initial guess on input
/// and the solution on output, on every process.
/// @throws PetscError if PETSc fails or CG does not converge within max_iterations
DistributedSolveReport solve_spd_distributed(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& b,
                                             Eigen::VectorXd& x, double tolerance, int max_iterations);

/// One BoomerAMG V-cycle through PETSc over the processes, z ≈ a⁻¹ r, set up once per matrix and
/// applied many times: the preconditioner of the coupled Schur-complement CG
/// (coupling/solvers/schur_cg_solver.cpp) when the pressure solver is `petsc`. r and z are whole
/// vectors on every process; the V-cycle itself runs distributed.
class DistributedAmg {
 public:
  DistributedAmg();
  ~DistributedAmg();
  DistributedAmg(DistributedAmg&&) noexcept;
  DistributedAmg& operator=(DistributedAmg&&) noexcept;

  /// Builds the hierarchy of `a` (symmetric, both triangles stored, n >= 1). @throws PetscError
  void setup(const Eigen::SparseMatrix<double>& a);
  /// z = one V-cycle applied to r. @throws std::logic_error before setup(), PetscError
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tetfsi::parallel
