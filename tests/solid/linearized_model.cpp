#include "tests/solid/linearized_model.hpp"

#include "solid/solid_error.hpp"

namespace tetfsi::solid {

LinearizedModel::LinearizedModel(const ElasticModel& base) : base_(base) {
  Eigen::VectorXd f;
  if (!base_.evaluate(Eigen::VectorXd::Zero(3 * base_.num_nodes()), f, &K0_))
    throw SolidError("LinearizedModel: the base model fails at rest: " + base_.last_error());
}

bool LinearizedModel::evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const {
  if (d.size() != K0_.rows()) throw SolidError("LinearizedModel::evaluate: displacement has the wrong size");
  if (!d.allFinite()) return false;
  force = K0_ * d;
  if (tangent) *tangent = K0_;
  return true;
}

}  // namespace tetfsi::solid
