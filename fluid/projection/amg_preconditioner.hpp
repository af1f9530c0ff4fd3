#pragma once
/// @file amg_preconditioner.hpp
/// One BoomerAMG V-cycle (hypre 2.26) as a symmetric positive definite preconditioner
/// z ≈ A⁻¹ r, set up once per matrix and applied many times: for solvers that own their Krylov
/// loop, such as the coupled Schur-complement CG (coupling/solvers/schur_cg_solver.cpp).
/// Same settings as the pressure solve's preconditioner (linear_solver.hpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace tetfsi::fluid {

class AmgPreconditioner {
 public:
  AmgPreconditioner();
  ~AmgPreconditioner();
  AmgPreconditioner(AmgPreconditioner&&) noexcept;
  AmgPreconditioner& operator=(AmgPreconditioner&&) noexcept;

  /// Builds the multigrid hierarchy of `a` (symmetric, both triangles stored, n >= 1).
  void setup(const Eigen::SparseMatrix<double>& a);
  /// z = one V-cycle applied to r (zero initial guess). @throws std::logic_error before setup()
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tetfsi::fluid
