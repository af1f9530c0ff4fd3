#include "solid/analysis/linear_analysis.hpp"

#include <Eigen/CholmodSupport>
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
  Mode mode;
  Eigen::VectorXd x = start;
  double lambda_old = 0;
  for (mode.iterations = 1; mode.iterations <= max_iterations; ++mode.iterations) {
    x = chol.solve(Eigen::VectorXd(mdof.cwiseProduct(x)));
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (fixed[i]) x[i] = 0;
    x /= std::sqrt(x.dot(mdof.cwiseProduct(x)));
    const double lambda = x.dot(K * x);
    if (std::abs(lambda - lambda_old) <= tolerance * lambda) break;
    lambda_old = lambda;
  }
  mode.omega = std::sqrt(x.dot(K * x));
  mode.shape = x;
  return mode;
}

}  // namespace tetfsi::solid
