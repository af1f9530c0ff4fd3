#include "solid/analysis/linear_analysis.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "solid/solid_error.hpp"

namespace tetfsi::solid {
namespace {

/// K0 with fixed rows and columns replaced by identity.
SparseMatrix constrained_stiffness(const ElasticModel& model, const std::vector<char>& fixed) {
  const int n = 3 * model.num_nodes();
  if (static_cast<int>(fixed.size()) != n) throw SolidError("linear analysis: fixed flags have the wrong size");
  Eigen::VectorXd f;
  SparseMatrix K;
  if (!model.evaluate(Eigen::VectorXd::Zero(n), f, &K))
    throw SolidError("linear analysis: the model fails at rest: " + model.last_error());
  for (int col = 0; col < K.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(K, col); it; ++it)
      if (fixed[col] || fixed[it.row()]) it.valueRef() = it.row() == col ? 1.0 : 0.0;
  return K;
}

using Cholesky = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;

void factorize(Cholesky& chol, const SparseMatrix& K) {
  chol.compute(K);
  if (chol.info() != Eigen::Success)
    throw SolidError("linear analysis: K0 on the free DOFs is not positive definite (fix enough nodes)");
}

}  // namespace

Eigen::VectorXd solve_linear_static(const ElasticModel& model, const std::vector<char>& fixed, const Eigen::VectorXd& f) {
  const SparseMatrix K = constrained_stiffness(model, fixed);
  Eigen::VectorXd rhs = f;
  for (Eigen::Index i = 0; i < rhs.size(); ++i)
    if (fixed[i]) rhs[i] = 0;
  Cholesky chol;
  factorize(chol, K);
  return chol.solve(rhs);
}

Mode lowest_mode(const ElasticModel& model, const std::vector<char>& fixed, const Eigen::VectorXd& start,
                 double tolerance, int max_iterations) {
  const SparseMatrix K = constrained_stiffness(model, fixed);
  Cholesky chol;
  factorize(chol, K);
  Eigen::VectorXd mdof = model.lumped_masses().replicate(1, 3).transpose().reshaped();
  for (Eigen::Index i = 0; i < mdof.size(); ++i)
    if (fixed[i]) mdof[i] = 0;
  // Subspace iteration with Rayleigh-Ritz on a block of 3 vectors (the start vector and two
  // fixed pseudo-random ones): converges at the rate omega_1^2 / omega_4^2 even when the
  // lowest frequency is (nearly) repeated, as for a square cantilever.
  const Eigen::Index n = start.size();
  Eigen::MatrixXd X(n, 3);
  X.col(0) = start;
  for (Eigen::Index i = 0; i < n; ++i) {
    X(i, 1) = std::sin(1.0 + 12.9898 * static_cast<double>(i));
    X(i, 2) = std::cos(2.0 + 78.233 * static_cast<double>(i));
  }
  Mode mode;
  double lambda_old = 0;
  for (mode.iterations = 1; mode.iterations <= max_iterations; ++mode.iterations) {
    Eigen::MatrixXd Y = chol.solve(Eigen::MatrixXd(mdof.asDiagonal() * X));
    for (Eigen::Index i = 0; i < n; ++i)
      if (fixed[i]) Y.row(i).setZero();
    const Eigen::MatrixXd Kr = Y.transpose() * (K * Y);
    const Eigen::MatrixXd Mr = Y.transpose() * mdof.asDiagonal() * Y;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(0.5 * (Kr + Kr.transpose()), 0.5 * (Mr + Mr.transpose()));
    if (ritz.info() != Eigen::Success) throw SolidError("lowest_mode: Rayleigh-Ritz step failed (degenerate start)");
    X = Y * ritz.eigenvectors();  // M-orthonormal Ritz vectors, ascending
    const double lambda = ritz.eigenvalues()[0];
    if (std::abs(lambda - lambda_old) <= tolerance * lambda) break;
    lambda_old = lambda;
  }
  Eigen::VectorXd x = X.col(0);
  x /= std::sqrt(x.dot(mdof.cwiseProduct(x)));
  mode.omega = std::sqrt(x.dot(K * x));
  mode.shape = x;
  return mode;
}

}  // namespace tetfsi::solid
