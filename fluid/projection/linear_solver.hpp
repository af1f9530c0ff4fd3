#pragma once
/// @file linear_solver.hpp
/// Symmetric positive definite sparse solves behind one small interface:
///  - kHypreAmgCg: CG preconditioned with one BoomerAMG V-cycle (hypre 2.26, one MPI rank; MPI is
///    initialised on first use if the caller has not done so, and finalised at exit).
///  - kPetscAmgCg: PETSc's CG with BoomerAMG (PCHYPRE), the rows spread over the MPI processes of
///    the run (`mpirun -n N`; parallel/distributed_solve.hpp); one process is fine too. The same
///    BoomerAMG settings as kHypreAmgCg, so the same answer to the tolerance.
///  - kEigenIcCg:  Eigen CG with IncompleteCholesky<double, Lower, NaturalOrdering<int>> (the natural
///    ordering converged much faster than the default AMD ordering on these matrices; shared probe).
/// Both stop at ||b - A x||_2 <= tolerance ||b||_2; the true residual is recomputed afterwards.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <stdexcept>
#include <string>

namespace tetfsi::fluid {

enum class SolverBackend { kHypreAmgCg, kEigenIcCg, kPetscAmgCg };

/// Parses "amg" / "ic" / "petsc" (for scene files and command lines). @throws std::invalid_argument otherwise.
SolverBackend parse_solver_backend(const std::string& name);
const char* to_string(SolverBackend backend);

struct SolverOptions {
  SolverBackend backend = SolverBackend::kHypreAmgCg;
  double tolerance = 1e-10;   ///< relative residual ||r|| / ||b||
  int max_iterations = 1000;
};

struct SolveReport {
  int iterations = 0;
  double relative_residual = 0.0;  ///< true ||b - A x|| / ||b|| after the solve
  double setup_seconds = 0.0;      ///< preconditioner set-up (AMG hierarchy / IC factorisation)
  double solve_seconds = 0.0;      ///< iterations
};

/// Thrown when the solver does not reach the tolerance or produces a non-finite value.
struct SolverError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Solves A x = b for symmetric positive definite A (both triangles stored). x is the initial
/// guess on input (resized to zero if its size is wrong) and the solution on output.
/// @throws SolverError if not converged within max_iterations or on NaN/Inf
SolveReport solve_spd(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                      const SolverOptions& options);

}  // namespace tetfsi::fluid
