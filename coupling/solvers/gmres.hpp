#pragma once
/// @file gmres.hpp
/// Private: restarted flexible GMRES with right preconditioning (Saad, "Iterative Methods for
/// Sparse Linear Systems", 2nd ed., Alg. 9.6, with Givens rotations as in Alg. 6.10), for
/// operators given as functions.
///
/// Solves K x = f for a square (possibly unsymmetric) K given only as y = K v, with a
/// preconditioner z = M⁻¹ v ≈ K⁻¹ v applied on the right: GMRES minimizes the true residual
/// ‖f − K x‖₂ over x₀ + M⁻¹ 𝒦ₖ(K M⁻¹, r₀), so the norm it monitors is the one the caller asks for,
/// whatever M is. Flexible: the preconditioned vectors zⱼ = M⁻¹vⱼ are kept and the update is
/// x = x₀ + Σ yⱼ zⱼ (Alg. 9.6), so K Zₖ = Vₖ₊₁ H̄ₖ holds for the zⱼ actually used even when M⁻¹ is
/// not exactly linear (a factor in single precision rounds each application): Alg. 9.5's
/// x₀ + M⁻¹(Vₖ y) would apply M⁻¹ once more to a combination and leave its rounding (1e-7 relative
/// for a float factor) in the residual, where the lagged solves stalled above a 1e-8 tolerance.
/// It keeps k more vectors and saves one preconditioner application per cycle.
///
/// Written by hand because K is only available as an operator (the coupled matrix applied block
/// by block): Eigen's unsupported GMRES needs a matrix type with Eigen's expression traits.
#include <Eigen/Core>
#include <functional>

namespace tetfsi::coupling::detail {

using LinearMap = std::function<void(const Eigen::VectorXd& in, Eigen::VectorXd& out)>;

struct GmresResult {
  int iterations = 0;     ///< Krylov steps (each one K product; restarts add one K product each)
  double residual = 0;    ///< ‖f − K x‖₂ of the returned x, recomputed from scratch
  bool converged = false;  ///< residual <= target
};

/// @param apply     y = K v
/// @param precondition z = M⁻¹ v
/// @param f         right-hand side
/// @param x         initial guess in, solution out (same size as f)
/// @param target    absolute residual ‖f − K x‖₂ to reach
/// @param max_iterations  cap on Krylov steps over all restarts
/// @param restart   Krylov subspace size before a restart (memory: 2 restart + 1 vectors)
/// A cycle ends early at a breakdown (the new Krylov vector is rounding noise, below 1e-14 of its
/// norm before orthogonalization); a cycle that does not reduce the true residual is undone and
/// GMRES returns (stagnation), so the returned x is the best iterate seen at a cycle boundary.
GmresResult right_preconditioned_gmres(const LinearMap& apply, const LinearMap& precondition, const Eigen::VectorXd& f,
                                       Eigen::VectorXd& x, double target, int max_iterations, int restart = 40);

}  // namespace tetfsi::coupling::detail
