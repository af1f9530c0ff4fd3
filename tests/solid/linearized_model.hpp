#pragma once
/// @file linearized_model.hpp
/// Small-displacement (linear) version of any ElasticModel: K(d) = K0 d, K'(d) = K0, with
/// K0 = K'(0) of the wrapped model, and strain energy 1/2 d^T K0 d. With it, the trapezoidal
/// integrator is exactly the linear trapezoidal (Newmark beta = 1/4, gamma = 1/2) scheme, which
/// conserves 1/2 u^T M u + 1/2 d^T K0 d (Krenk 2006); used by the validation tests
/// (energy, period, cantilever statics and modes).
#include "solid/elastic_model.hpp"

namespace tetfsi::solid {

class LinearizedModel : public ElasticModel {
 public:
  /// Evaluates K'(0) of `base` once. @throws SolidError if base cannot evaluate at rest.
  explicit LinearizedModel(const ElasticModel& base);

  int num_nodes() const override { return base_.num_nodes(); }
  const Eigen::VectorXd& reference_positions() const override { return base_.reference_positions(); }
  const Eigen::VectorXd& lumped_masses() const override { return base_.lumped_masses(); }
  bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const override;
  double strain_energy(const Eigen::VectorXd& d) const override { return 0.5 * d.dot(K0_ * d); }
  const SparseMatrix& stiffness() const { return K0_; }

 private:
  const ElasticModel& base_;
  SparseMatrix K0_;
};

}  // namespace tetfsi::solid
