#pragma once
/// @file coupled_solver.hpp
/// Three solvers for the simultaneous system of eq. (7) (coupled_system.hpp) behind one interface,
/// all converging to the same solution:
///
///  - `umfpack`  : sparse LU of the paper-form matrix [A −Hᵀ; H P] with UMFPACK, 64-bit indices
///                 (umfpack_dl; the int interface fails beyond ~500k unknowns). The reference.
///  - `bicgstab` : BiCGSTAB on the same unsymmetric matrix, as in the paper (§3.3), preconditioned
///                 by the block-diagonal incomplete Cholesky diag(IC(A), IC(Ŝ)) with
///                 Ŝ = P + H diag(A)⁻¹ Hᵀ.
///  - `schur_cg` : the fast path using the symmetric structure (Benzi, Golub & Liesen 2005, sec. 5): eliminate
///                 u = A⁻¹(b + Hᵀp), solve the SPD Schur complement
///                     (P + H A⁻¹ Hᵀ) p = r − H A⁻¹ b
///                 by preconditioned CG with A factored once by CHOLMOD (A is the smaller, solid
///                 block), then recover u. Its preconditioner is IC(Ŝ) by default, or any SPD
///                 approximation the caller plugs in (e.g. BoomerAMG of Ŝ).
///                 From the second step on (option `reuse_factorization`), it keeps the Cholesky
///                 factor of an earlier A and the preconditioner of an earlier Ŝ, and solves the
///                 whole system [A −Hᵀ; H P] by GMRES right-preconditioned with the block lower
///                 triangle [Â 0; H Ŝ] of those lagged blocks (reported as `block_gmres+…`): with
///                 exact blocks K P⁻¹ = P [I −A⁻¹Hᵀ; 0 I] P⁻¹, whose minimal polynomial has degree
///                 2, so the iterations are those of the Ŝ-preconditioned Schur complement
///                 (Murphy, Golub & Wathen, SIAM J. Sci. Comput. 21, 2000) plus the drift of Â.
///                 The residual GMRES stops on is that of the current system, so the answer is
///                 the same to the tolerance. A alone is refactorized once the lagged solves' extra
///                 iterations (beyond the last fresh solve's) since its factorization add up to half
///                 a fresh solve's (its numeric factorization costs about that much; the drift of Â
///                 is what makes the iterations grow). Both blocks are rebuilt once the extra
///                 iterations since the last fresh solve add up to twice a fresh solve's, or
///                 when GMRES misses its cap (3x a fresh solve's iterations + 20), in which case the
///                 step is solved fresh; a new pattern of A rebuilds the factor, a remeshed fluid
///                 (new P or H pattern) only Ŝ's preconditioner. If the refactorization fails (A
///                 indefinite), the last SPD factor is kept, Ŝ's preconditioner is rebuilt, GMRES
///                 solves the step, and the next attempt waits for another two solves' worth of
///                 extra iterations. The time-splitting baseline's separate solid (m = 0) and
///                 fluid (n = 0) solves are always fresh.
/// No solver falls back to another silently: each reports its name, iterations and residuals,
/// and a solve that does not reach its tolerance throws CoupledSolveError.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>

#include "coupling/coupled_system.hpp"

namespace tetfsi {
class BinaryWriter;
class BinaryReader;
}  // namespace tetfsi

namespace tetfsi::coupling {

enum class CoupledSolverKind { Umfpack, BiCGSTAB, SchurCG };

/// Parses "umfpack", "bicgstab" or "schur_cg"; throws std::invalid_argument otherwise.
CoupledSolverKind parse_coupled_solver_kind(const std::string& name);
std::string to_string(CoupledSolverKind kind);

struct CoupledSolverOptions {
  double tolerance = 1e-10;   ///< relative residual of each block row (residuals()) to reach
  int max_iterations = 2000;  ///< iterative solvers only
  /// schur_cg only: optional SPD preconditioner z ≈ Ŝ⁻¹ r for the pressure Schur complement, set
  /// up by `setup` on Ŝ = P + H diag(A)⁻¹ Hᵀ. Empty: incomplete Cholesky of Ŝ.
  std::function<void(const SparseMatrix& S_hat)> preconditioner_setup;
  std::function<void(const Eigen::VectorXd& r, Eigen::VectorXd& z)> preconditioner_apply;
  std::string preconditioner_name;  ///< reported in stats (e.g. "boomeramg")
  /// schur_cg only: keep A's factor and Ŝ's preconditioner from step to step (see above).
  bool reuse_factorization = true;
  /// schur_cg only: keep Ŝ, the matrix its preconditioner was set up on, for write_state (a
  /// checkpoint stores it and reading sets the preconditioner up again). A run that writes no
  /// checkpoints sets false: Ŝ is then freed once its preconditioner is set up (44 MB at 962k
  /// fluid tets on the flagship) and write_state throws std::logic_error.
  bool keep_checkpoint_state = true;
};

/// What a solve did; written to stats.csv by the runner.
struct CoupledSolveReport {
  std::string solver;         ///< e.g. "schur_cg+ic"
  int iterations = 0;         ///< outer iterations (0 for the direct solver)
  BlockResiduals residual;    ///< of the returned solution, in the original (unscaled) system
  double setup_seconds = 0;   ///< factorizations and preconditioner set-up
  double solve_seconds = 0;
  int factor_age = 0;         ///< schur_cg: solves since A was last factorized (0: this solve)
  int contact_rounds = 0;     ///< solves of the step's contact active set (CoupledStepper; 0: no obstacles)
  int contacts = 0;           ///< solid nodes held by a contact constraint at the end of the step
};

struct CoupledSolveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CoupledSolver {
 public:
  virtual ~CoupledSolver() = default;
  /// Solves eq. (7) for u^{n+1} (size n) and p^{n+1} (size m). `u` and `p` may hold an initial
  /// guess (iterative solvers use it when its sizes match).
  /// @throws CoupledSolveError if the tolerance is not reached, std::invalid_argument on bad sizes
  virtual CoupledSolveReport solve(const CoupledSystem& system, Eigen::VectorXd& u, Eigen::VectorXd& p) = 0;
  /// The next solve must not lean on anything kept from earlier solves (schur_cg's lagged
  /// factor): the caller changed A by more than a step's drift (contact penalty rows).
  virtual void request_fresh_solve() {}
  /// Checkpoints (schur_checkpoint.cpp): what a solver keeps between solves and that changes its
  /// answers (schur_cg's lagged factor and preconditioner, rebuilt from the matrices they were
  /// made of, and its counters). The direct and BiCGSTAB solvers keep nothing.
  virtual void write_state(BinaryWriter& /*out*/) const {}
  virtual void read_state(BinaryReader& /*in*/) {}
};

std::unique_ptr<CoupledSolver> make_coupled_solver(CoupledSolverKind kind, CoupledSolverOptions options = {});

}  // namespace tetfsi::coupling
