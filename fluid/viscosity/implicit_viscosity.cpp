#include "fluid/viscosity/implicit_viscosity.hpp"

#include "fluid/viscosity/node_fit.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <sstream>

namespace tetfsi::fluid::viscous_detail {
class ViscousOperator;
}  // namespace tetfsi::fluid::viscous_detail

namespace Eigen::internal {
template <>
struct traits<tetfsi::fluid::viscous_detail::ViscousOperator> : public traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace tetfsi::fluid {
namespace viscous_detail {

/// Per tet, the coefficient c_t of the stress (c_t (G_t + G_t^T) = c_t 2 eps_t for G_t the gradient
/// of the nodal field on t), gathered per node: out_i = sum_{t ni i} c_t (G_t + G_t^T) grad(phi_i)|_t.
/// Tets in ascending order per node (node_tets), nodes in parallel: deterministic.
/// `stress` is scratch, one matrix per tet (kept by the caller: CG applies this every iteration).
void gather_stress(const FluidMesh& mesh, const std::vector<double>& coefficient, const Eigen::VectorXd& x,
                   Eigen::VectorXd& out, std::vector<Eigen::Matrix3d>& stress) {
  // Chunks of kGrain tets or nodes per task: the per-item work is a few dozen flops, so TBB's
  // default splitting down to single items cost more than the work.
  constexpr int kGrain = 1024;
  stress.resize(mesh.num_tets());
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_tets(), kGrain), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t) {
      if (coefficient[t] == 0.0) continue;
      Eigen::Matrix3d G = Eigen::Matrix3d::Zero();  // G_ab = sum_k x_{k,a} (grad phi_k)_b
      for (int k = 0; k < 4; ++k) G.noalias() += x.segment<3>(3 * mesh.tets[t][k]) * mesh.grad[t][k].transpose();
      stress[t] = coefficient[t] * (G + G.transpose());
    }
  });
  out.resize(3 * mesh.num_nodes());
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_nodes(), kGrain), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i < r.end(); ++i) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int t : mesh.node_tets[i]) {
        if (coefficient[t] == 0.0) continue;
        int k = 0;
        while (mesh.tets[t][k] != i) ++k;
        sum.noalias() += stress[t] * mesh.grad[t][k];
      }
      out.segment<3>(3 * i) = sum;
    }
  });
}

/// The increment's operator A dU = rho M dU + h K dU on the free nodes, the identity on the others
/// (Dirichlet nodes and nodes without fluid), applied without assembling K.
class ViscousOperator : public Eigen::EigenBase<ViscousOperator> {
 public:
  using Scalar = double;
  using RealScalar = double;
  using StorageIndex = int;
  enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };

  ViscousOperator(const FluidMesh& mesh, std::vector<double> h_coefficient, Eigen::VectorXd mass, std::vector<char> free,
                  std::vector<Eigen::Matrix3d> scratch)
      : mesh_(&mesh), h_coefficient_(std::move(h_coefficient)), mass_(std::move(mass)), free_(std::move(free)),
        stress_(std::move(scratch)) {}
  Eigen::Index rows() const { return 3 * mesh_->num_nodes(); }
  Eigen::Index cols() const { return rows(); }

  template <class Rhs>
  Eigen::Product<ViscousOperator, Rhs, Eigen::AliasFreeProduct> operator*(const Eigen::MatrixBase<Rhs>& x) const {
    return Eigen::Product<ViscousOperator, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
  }

  void apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
    gather_stress(*mesh_, h_coefficient_, x, y, stress_);
    for (int i = 0; i < mesh_->num_nodes(); ++i) {
      if (free_[i]) y.segment<3>(3 * i) += mass_[i] * x.segment<3>(3 * i);
      else y.segment<3>(3 * i) = x.segment<3>(3 * i);
    }
  }

  /// 1 / A_jj: rho M_i + h sum_t c_t (|grad phi_i|^2 + (grad phi_i)_a^2) on the free nodes, 1 elsewhere.
  Eigen::VectorXd inverse_diagonal() const {
    Eigen::VectorXd d = Eigen::VectorXd::Ones(rows());
    for (int i = 0; i < mesh_->num_nodes(); ++i) {
      if (!free_[i]) continue;
      Eigen::Vector3d di = Eigen::Vector3d::Constant(mass_[i]);
      for (int t : mesh_->node_tets[i]) {
        int k = 0;
        while (mesh_->tets[t][k] != i) ++k;
        const Eigen::Vector3d& g = mesh_->grad[t][k];
        di += h_coefficient_[t] * (Eigen::Vector3d::Constant(g.squaredNorm()) + g.cwiseProduct(g));
      }
      d.segment<3>(3 * i) = di.cwiseInverse();
    }
    return d;
  }

 private:
  const FluidMesh* mesh_;
  std::vector<double> h_coefficient_;  ///< h w_t mu_t
  Eigen::VectorXd mass_;               ///< rho M_i
  std::vector<char> free_;
  mutable std::vector<Eigen::Matrix3d> stress_;  ///< gather_stress's scratch
};

/// Jacobi preconditioner for the matrix-free operator (Eigen's DiagonalPreconditioner reads matrix
/// coefficients, which the operator does not store).
class JacobiPreconditioner {
 public:
  JacobiPreconditioner() = default;
  template <class M>
  JacobiPreconditioner& analyzePattern(const M&) { return *this; }
  template <class M>
  JacobiPreconditioner& factorize(const M& m) { return compute(m); }
  template <class M>
  JacobiPreconditioner& compute(const M& m) {
    inverse_diagonal_ = m.inverse_diagonal();
    return *this;
  }
  template <class Rhs>
  Eigen::VectorXd solve(const Eigen::MatrixBase<Rhs>& b) const { return inverse_diagonal_.cwiseProduct(b); }
  Eigen::ComputationInfo info() const { return Eigen::Success; }

 private:
  Eigen::VectorXd inverse_diagonal_;
};

}  // namespace viscous_detail
}  // namespace tetfsi::fluid

namespace Eigen::internal {
template <class Rhs>
struct generic_product_impl<tetfsi::fluid::viscous_detail::ViscousOperator, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<tetfsi::fluid::viscous_detail::ViscousOperator, Rhs,
                                generic_product_impl<tetfsi::fluid::viscous_detail::ViscousOperator, Rhs>> {
  template <class Dest>
  static void scaleAndAddTo(Dest& dst, const tetfsi::fluid::viscous_detail::ViscousOperator& lhs, const Rhs& rhs,
                            const double& alpha) {
    Eigen::VectorXd y;
    lhs.apply(rhs, y);
    dst += alpha * y;
  }
};
}  // namespace Eigen::internal

namespace tetfsi::fluid {

ViscosityReport apply_viscosity(const FluidMesh& mesh, const std::vector<double>& viscosity,
                                const std::vector<double>& weight, double density, const ViscousNodes& nodes,
                                double h, const SolverOptions& options, TetVectors& u,
                                const std::vector<std::vector<int>>* rings) {
  const auto start = std::chrono::steady_clock::now();
  const int N = mesh.num_nodes(), T = mesh.num_tets();
  // W: the fluid volume around each node (M_i = W_i / 4); U: the fits' value at the free nodes, the
  // prescribed velocity at the Dirichlet nodes.
  Eigen::VectorXd W = Eigen::VectorXd::Zero(N);
  for (int t = 0; t < T; ++t)
    for (int k = 0; k < 4; ++k) W[mesh.tets[t][k]] += weight[t];
  const NodeFits fits = fit_at_nodes(mesh, weight, u, rings ? *rings : node_rings(mesh));
  Eigen::VectorXd U(3 * N);
  for (int i = 0; i < N; ++i) U.segment<3>(3 * i) = fits.at_node(i);
  std::vector<char> free(N);
  for (int i = 0; i < N; ++i) {
    free[i] = !nodes.fixed[i] && W[i] > 0;
    if (nodes.fixed[i]) U.segment<3>(3 * i) = nodes.velocity[i];
  }
  std::vector<double> h_coefficient(T);
  for (int t = 0; t < T; ++t) h_coefficient[t] = h * weight[t] * viscosity[t];
  // b = -h K U on the free nodes, 0 elsewhere.
  Eigen::VectorXd b;
  std::vector<Eigen::Matrix3d> stress;
  viscous_detail::gather_stress(mesh, h_coefficient, U, b, stress);
  b = -b;
  for (int i = 0; i < N; ++i)
    if (!free[i]) b.segment<3>(3 * i).setZero();
  const viscous_detail::ViscousOperator A(mesh, std::move(h_coefficient), density * 0.25 * W, free, std::move(stress));
  Eigen::ConjugateGradient<viscous_detail::ViscousOperator, Eigen::Lower | Eigen::Upper,
                           viscous_detail::JacobiPreconditioner>
      cg;
  cg.setTolerance(options.tolerance);
  cg.setMaxIterations(options.max_iterations);
  cg.compute(A);
  const Eigen::VectorXd dU = cg.solve(b);
  ViscosityReport rep;
  rep.iterations = static_cast<int>(cg.iterations());
  rep.relative_residual = cg.error();
  if (cg.info() != Eigen::Success || !dU.allFinite())
  {
    std::ostringstream message;
    message.precision(3);
    message << "viscosity: CG reached a relative residual of " << cg.error() << " in " << cg.iterations()
            << " iterations (tolerance " << options.tolerance << ", limit " << options.max_iterations << ")";
    throw SolverError(message.str());
  }
  // The reaction -(K U^{n+1})_i at the Dirichlet nodes, from the tets around each (not a gather
  // over the whole mesh: the Dirichlet nodes are the boundary's).
  const Eigen::VectorXd U_next = U + dU;
  rep.wall_force.assign(N, Eigen::Vector3d::Zero());
  rep.wall_stiffness.assign(N, Eigen::Matrix3d::Zero());
  for (int i = 0; i < N; ++i) {
    if (!nodes.fixed[i]) continue;
    for (int t : mesh.node_tets[i]) {
      const double c = weight[t] * viscosity[t];
      if (c == 0.0) continue;
      int k = 0;
      while (mesh.tets[t][k] != i) ++k;
      const Eigen::Vector3d& g = mesh.grad[t][k];
      Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
      for (int j = 0; j < 4; ++j) G.noalias() += U_next.segment<3>(3 * mesh.tets[t][j]) * mesh.grad[t][j].transpose();
      rep.wall_force[i] -= c * (G + G.transpose()) * g;
      rep.wall_stiffness[i] += c * (g.squaredNorm() * Eigen::Matrix3d::Identity() + g * g.transpose());
    }
  }
  // u_t <- u_t + (P dU)_t - (1 - beta_t) (u_t - r_t): the nodal increment, and the tet's sub-cell
  // fluctuation about its smooth reference r_t = (1/4) sum_k q_{t_k}(c_t) (node_fit.hpp; at a
  // Dirichlet node k, q_k + U_k - q_k(x_k)) decaying as the finest
  // mode the tet holds, beta_t = 1 / (1 + h nu_t sum_k |grad phi_k|^2).
  tbb::parallel_for(0, T, [&](int t) {
    if (!(weight[t] > 0)) return;
    Eigen::Vector3d mean_dU = Eigen::Vector3d::Zero(), reference = Eigen::Vector3d::Zero();
    double stiffness = 0;
    for (int k = 0; k < 4; ++k) {
      const int i = mesh.tets[t][k];
      mean_dU += 0.25 * dU.segment<3>(3 * i);
      // At a Dirichlet node, the fit shifted to take the prescribed value at the node.
      reference += 0.25 * fits.at(mesh, i, mesh.centroid(t));
      if (nodes.fixed[i]) reference += 0.25 * (nodes.velocity[i] - fits.at_node(i));
      stiffness += mesh.grad[t][k].squaredNorm();
    }
    const double beta = 1.0 / (1.0 + h * viscosity[t] / density * stiffness);
    u[t] += mean_dU - (1.0 - beta) * (u[t] - reference);
  });
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return rep;
}

}  // namespace tetfsi::fluid
