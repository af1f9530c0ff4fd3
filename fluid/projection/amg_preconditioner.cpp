#include "fluid/projection/amg_preconditioner.hpp"

#include <optional>
#include <stdexcept>

#include "fluid/projection/hypre_support.hpp"

namespace tetfsi::fluid {

struct AmgPreconditioner::Impl {
  explicit Impl(const Eigen::SparseMatrix<double>& a)
      : matrix(a), zeros(Eigen::VectorXd::Zero(a.rows())), r(matrix.rows(), zeros.data()), z(matrix.rows(), zeros.data()),
        amg(hypre::make_boomeramg_preconditioner()) {
    HYPRE_BoomerAMGSetup(amg, matrix.par(), r.par(), z.par());
  }
  ~Impl() { HYPRE_BoomerAMGDestroy(amg); }
  hypre::Matrix matrix;  // declared first: the vectors refer to its row list
  Eigen::VectorXd zeros;
  hypre::Vector r, z;
  HYPRE_Solver amg;
};

AmgPreconditioner::AmgPreconditioner() = default;
AmgPreconditioner::~AmgPreconditioner() = default;
AmgPreconditioner::AmgPreconditioner(AmgPreconditioner&&) noexcept = default;
AmgPreconditioner& AmgPreconditioner::operator=(AmgPreconditioner&&) noexcept = default;

void AmgPreconditioner::setup(const Eigen::SparseMatrix<double>& a) {
  if (a.rows() < 1 || a.rows() != a.cols()) throw std::invalid_argument("AmgPreconditioner: square matrix of size >= 1 expected");
  impl_.reset();
  impl_ = std::make_unique<Impl>(a);
}

void AmgPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  if (!impl_) throw std::logic_error("AmgPreconditioner::apply before setup");
  impl_->r.set(r.data());
  impl_->z.set(impl_->zeros.data());
  HYPRE_BoomerAMGSolve(impl_->amg, impl_->matrix.par(), impl_->r.par(), impl_->z.par());
  z.resize(r.size());
  impl_->z.get(z.data());
}

}  // namespace tetfsi::fluid
