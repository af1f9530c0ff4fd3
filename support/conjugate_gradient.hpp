#pragma once
/// @file conjugate_gradient.hpp
/// Preconditioned conjugate gradients for a symmetric positive definite operator K given as a
/// function (Saad, "Iterative Methods for Sparse Linear Systems", 2nd ed. 2003, Alg. 9.1):
///
///     z₀ = M⁻¹r₀, d₀ = z₀;  αₖ = (rₖ·zₖ) / (dₖ·K dₖ),  xₖ₊₁ = xₖ + αₖ dₖ,  rₖ₊₁ = rₖ − αₖ K dₖ,
///     zₖ₊₁ = M⁻¹rₖ₊₁,  dₖ₊₁ = zₖ₊₁ + (rₖ₊₁·zₖ₊₁ / rₖ·zₖ) dₖ.
///
/// Written out because the operators it serves are functions (the pressure Schur complement
/// P + H A⁻¹ Hᵀ, a BoomerAMG V-cycle as M⁻¹); Eigen's ConjugateGradient takes matrix and
/// preconditioner classes with its expression traits.
#include <Eigen/Core>

namespace tetfsi {

/// Iterates from x until ‖r‖ ≤ target or `max_iterations` iterations.
/// @param apply          apply(v, y): y = K v
/// @param precondition   precondition(r, z): z ≈ K⁻¹ r (SPD)
/// @param residual       in: r₀ = b − K x; out: the recursively updated residual at the last iterate
/// @param x              in: the initial guess; out: the last iterate
/// @return the iterations taken
template <class Apply, class Precondition>
int preconditioned_cg(const Apply& apply, const Precondition& precondition, Eigen::VectorXd& residual,
                      Eigen::VectorXd& x, double target, int max_iterations) {
  Eigen::VectorXd z(x.size()), direction(x.size()), product(x.size());
  double rz_previous = 0;
  int k = 0;
  for (; k < max_iterations && residual.norm() > target; ++k) {
    precondition(residual, z);
    const double rz = residual.dot(z);
    if (k == 0) direction = z;
    else direction = z + (rz / rz_previous) * direction;
    rz_previous = rz;
    apply(direction, product);
    const double alpha = rz / direction.dot(product);
    x += alpha * direction;
    residual -= alpha * product;
  }
  return k;
}

}  // namespace tetfsi
