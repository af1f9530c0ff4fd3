/// @file schur_checkpoint.cpp
/// SchurCGSolver::write_state / read_state: the lagged blocks of the fast path (coupled_solver.hpp)
/// in a checkpoint. The factor and the preconditioner are not stored as such: the matrices they
/// were computed from are, and reading factorizes and sets up again (the same bits: CHOLMOD, the
/// incomplete Cholesky and BoomerAMG are deterministic for a given matrix).
#include <stdexcept>

#include "coupling/solvers/schur_state.hpp"
#include "support/binary_stream.hpp"

namespace tetfsi::coupling::detail {

void SchurCGSolver::write_state(BinaryWriter& out) const {
  if (!options_.keep_checkpoint_state)
    throw std::logic_error("schur_cg: write_state needs CoupledSolverOptions::keep_checkpoint_state (Ŝ was freed)");
  const Lag& lag = *lag_;
  out(factor_->valid);
  if (factor_->valid) out(factor_->matrix);
  out(bool(lag.precondition));
  if (lag.precondition) out(lag.S_hat, lag.P_pattern.outer, lag.P_pattern.inner, lag.H_pattern.outer, lag.H_pattern.inner);
  out(lag.fresh_iterations, lag.age, lag.extra_iterations, lag.factor_extra_iterations, lag.refresh, lag.coupling_share,
      lag.decoupled, lag.double_factor);
}

void SchurCGSolver::read_state(BinaryReader& in) {
  Lag& lag = *lag_;
  bool valid = false, preconditioned = false;
  in(valid);
  factor_->valid = false;
  if (valid) {
    SparseMatrix A;
    in(A);
    if (!factor_->factorize(A)) in.fail("a solid block that no longer factorizes");
  }
  in(preconditioned);
  lag.precondition = nullptr;
  if (preconditioned) {
    in(lag.S_hat, lag.P_pattern.outer, lag.P_pattern.inner, lag.H_pattern.outer, lag.H_pattern.inner);
    if (lag.S_hat.rows() > 0 && !set_up_preconditioner()) in.fail("a Schur approximation whose preconditioner fails");
    set_preconditioner();
  }
  in(lag.fresh_iterations, lag.age, lag.extra_iterations, lag.factor_extra_iterations, lag.refresh, lag.coupling_share,
     lag.decoupled, lag.double_factor);
}

}  // namespace tetfsi::coupling::detail
