#pragma once
/// @file schur_state.hpp
/// Private: what the fast path (SchurCGSolver) keeps between solves: the CHOLMOD factor of the
/// solid block A, and, for the lagged solves, the preconditioner of Ŝ and the patterns it was
/// built for (see coupled_solver.hpp).
#include <Eigen/IterativeLinearSolvers>
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "coupling/solvers/block_cholesky.hpp"
#include "coupling/solvers/solver_impls.hpp"

namespace tetfsi::coupling::detail {

/// The sparsity pattern (outer and inner indices) of a compressed matrix, to tell whether a
/// factorization or preconditioner built for one matrix still fits another.
struct SparsityPattern {
  std::vector<SparseMatrix::StorageIndex> outer, inner;

  bool matches(const SparseMatrix& a) const {
    return a.isCompressed() && outer.size() == static_cast<std::size_t>(a.outerSize() + 1) &&
           inner.size() == static_cast<std::size_t>(a.nonZeros()) &&
           std::equal(outer.begin(), outer.end(), a.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), a.innerIndexPtr());
  }
  /// Records a's pattern (an uncompressed matrix records nothing, so it never matches).
  void assign(const SparseMatrix& a) {
    outer.clear(), inner.clear();
    if (!a.isCompressed()) return;
    outer.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1);
    inner.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  }
};

/// Supernodal Cholesky of A = M/h + C + (h/2)K′ (SPD for a stable step), one factor per solid body
/// (block_cholesky.hpp). The fill-reducing
/// ordering and symbolic factor (CHOLMOD's analysis) depend only on A's sparsity pattern, which
/// stays the same from step to step while the solid meshes do (the remesher freezes them), so
/// they are computed once per pattern and only the numeric factorization is redone, in place (a
/// failed one is undone by factorizing `matrix` again: SchurCGSolver::refactor), so one numeric
/// factor is held (42 MB at 48³ in bench_coupling, 126 MB at 962k fluid tets on the flagship), in
/// single precision (half that) once it only preconditions the lagged solves; a factorization
/// after that allocates the double values again, and the conversion holds both for a moment.
struct SchurCGSolver::Factor {
  BlockCholesky cholesky;   // one CHOLMOD factor per solid body, solved in parallel
  SparsityPattern pattern;  // of the A the analysis was made for
  bool valid = false;       // cholesky holds the factor of an SPD matrix with that pattern
  SparseMatrix matrix;      // the A of the last factorize(), for checkpoints (schur_checkpoint.cpp)

  /// Factorizes A, re-analysing only when its pattern changed. Returns false if A is not SPD.
  bool factorize(const SparseMatrix& A) {
    matrix = A;
    if (!pattern.matches(A)) {
      cholesky.analyze_pattern(A);
      pattern.assign(A);
    }
    valid = cholesky.factorize(A);
    return valid;
  }
};

/// State of the lagged solves: Ŝ's preconditioner and the patterns of P and H it was set up
/// for (Ŝ = P + H diag(A)⁻¹ Hᵀ has the pattern of P + H Hᵀ), and the iterations of the last
/// fresh solve that decide when to rebuild.
struct SchurCGSolver::Lag {
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>> ic;  // without a caller's preconditioner
  std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)> precondition;     // z ≈ Ŝ⁻¹ r
  std::string preconditioner_name;
  SparsityPattern P_pattern, H_pattern;
  SparseMatrix S_hat;        // the Ŝ the preconditioner was set up on, for checkpoints
  int fresh_iterations = 0;  // CG iterations of the last fresh solve
  int age = 0;               // solves since A was last factorized
  int extra_iterations = 0;  // iterations of the lagged solves since the last fresh one beyond fresh_iterations, summed
  int factor_extra_iterations = 0;  // the same, since A was last factorized
  bool refresh = true;       // rebuild both blocks at the next solve
  /// Mean over the last lagged solve's iterations of ‖H zᵤ‖ / ‖σ_f vₚ‖: how much the solid's
  /// answer zᵤ = Â⁻¹ σₛvᵤ changes the fluid block's right-hand side in the block-triangular
  /// preconditioner (lagged_gmres.cpp).
  double coupling_share = 1.0;
  /// Precondition with diag(Â, Ŝ), the two blocks side by side, instead of the block triangle:
  /// set when coupling_share < kDecoupledBelow. Measured on the CI scenes (iterations of the
  /// lagged solves, triangular → diagonal): smoke on rubber sheets (share 0.006) 391 → 394;
  /// liquids on solids (share 0.14-0.98) 221 → 525, 1,376 → 1,864, 2,229 → 2,815.
  bool decoupled = false;
  static constexpr double kDecoupledBelow = 0.05;
  /// Keep Â's factor in double: a lagged solve with it in single precision missed its cap
  /// (BlockCholesky's condition gate is only a bound; the run does not try single again).
  bool double_factor = false;

  /// Refactorize A alone (Ŝ's preconditioner kept) once the lagged factor's extra iterations add up
  /// to half a fresh solve's: the rent-or-buy rule with A's numeric factorization costing about
  /// half a fresh solve (measured on the flagship, 2 cores: 0.04 s against 3.2 ms per iteration
  /// at 99k fluid tets, 0.17 s against 14.5 ms at 409k, i.e. 12 iterations where a fresh solve
  /// takes 18-20). The drift of Â is what makes the lagged iterations grow (at 409k: 20 → 29 over
  /// 11 steps with both blocks lagged, 18-19 throughout with A refactorized every step).
  bool factor_due() const { return factor_extra_iterations >= std::max(fresh_iterations / 2, 1); }
};

}  // namespace tetfsi::coupling::detail
