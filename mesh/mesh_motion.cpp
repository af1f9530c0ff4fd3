#include "mesh/mesh_motion.hpp"

#include "support/binary_stream.hpp"
#include "support/conjugate_gradient.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <cmath>
#include <utility>

#include "mesh/column_gather.hpp"
#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/incidence.hpp"
#include "mesh/remesh_region.hpp"   // vertex_kinds

namespace tetfsi::mesh {
namespace {

/// Gradients of the four P1 basis functions of a tet (rows), and its volume.
Eigen::Matrix<double, 4, 3> p1_gradients(const std::array<Eigen::Vector3d, 4>& x, double& volume) {
  Eigen::Matrix3d D;
  for (int k = 0; k < 3; ++k) D.col(k) = x[k + 1] - x[0];
  volume = D.determinant() / 6.0;
  const Eigen::Matrix3d Dinv_t = D.inverse().transpose();  // columns: gradients of φ1, φ2, φ3
  Eigen::Matrix<double, 4, 3> g;
  for (int k = 0; k < 3; ++k) g.row(k + 1) = Dinv_t.col(k).transpose();
  g.row(0) = -(g.row(1) + g.row(2) + g.row(3));
  return g;
}

/// The matrix Σ_t k_t over the fluid tets, restricted to rows `row_of[v]` >= 0 (num_rows of them)
/// and to the columns of the vertices in `column_vertex` (column c: vertex column_vertex[c]), where
/// column b of k_t, k_t e_b = stiffness_column(t, b), couples the tet's four vertices with its b-th
/// (only fluid tets: is_fluid(t)). Column c sums its vertex's tets in ascending order
/// (column_gather.hpp), the order in which setFromTriplets on triplets pushed tet by tet sums
/// them: each entry is that sum bit for bit.
template <class IsFluid, class StiffnessColumn>
Eigen::SparseMatrix<double> gather_block_columns(const TetMesh& mesh, const VertexIncidence& incidence,
                                                 const IsFluid& is_fluid, const StiffnessColumn& stiffness_column,
                                                 const std::vector<int>& row_of, int num_rows,
                                                 const std::vector<int>& column_vertex) {
  return gather_columns(num_rows, static_cast<int>(column_vertex.size()), [&](int c, const auto& emit) {
    const int v = column_vertex[c];
    for (int e = incidence.start[v]; e < incidence.start[v + 1]; ++e) {
      const int t = incidence.element[e], b = incidence.local[e];
      if (!is_fluid(t)) continue;
      const Eigen::Vector4d kt_b = stiffness_column(t, b);
      for (int a = 0; a < 4; ++a) {
        const int r = row_of[mesh.tets[t][a]];
        if (r >= 0) emit(r, [&] { return kt_b[a]; });
      }
    }
  });
}

}  // namespace

struct MeshMotion::Solver {
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  // options.factorize: CHOLMOD's supernodal Cholesky, whose solve takes the three displacement
  // components as one block right-hand side (one pass over the factor instead of three; measured
  // motion 0.094 s -> 0.025 s per step at 32³ cells against Eigen's SimplicialLDLT, bench_coupling).
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky;
  bool factorized = false;
};

MeshMotion::MeshMotion(const TetMesh& mesh, const MeshMotionOptions& options)
    : reference_(mesh.vertices), kind_(vertex_kinds(mesh)), unknown_(mesh.num_vertices(), -1),
      solver_(std::make_unique<Solver>()) {
  const int n = mesh.num_vertices();
  int m = 0;
  for (int v = 0; v < n; ++v) {
    if (kind_[v] == 0) unknown_[v] = m++;
    if (kind_[v] == 1) prescribed_.push_back(v);
  }
  double v_max = 0;
  auto is_fluid = [&](int t) { return mesh.subdomain[t] == kFluidSubdomain; };
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (is_fluid(t)) v_max = std::max(v_max, signed_volume(mesh, t));
  auto p1_gradients_of = [&](int t, double& volume) {
    const auto& tet = mesh.tets[t];
    return p1_gradients({mesh.vertices[tet[0]], mesh.vertices[tet[1]], mesh.vertices[tet[2]], mesh.vertices[tet[3]]},
                        volume);
  };
  // The first flat or inverted fluid tet (the lowest index, whatever the thread count).
  std::atomic<int> first_flat{std::numeric_limits<int>::max()};
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_tets()), [&](const tbb::blocked_range<int>& range) {
    for (int t = range.begin(); t < range.end(); ++t) {
      double v = 0;
      if (!is_fluid(t)) continue;
      p1_gradients_of(t, v);
      for (int cur = first_flat.load(); !(v > 0) && t < cur && !first_flat.compare_exchange_weak(cur, t);) {}
    }
  });
  if (first_flat.load() != std::numeric_limits<int>::max())
    throw MeshError("mesh motion: fluid tet " + std::to_string(first_flat.load()) + " is flat or inverted");
  // Column b of k_t = s_t V_t G_t G_tᵀ with s_t = (V_max / V_t)^χ, computed where the gather reads
  // it (four times per tet) rather than stored: the stored 4 x 4 blocks were 128 bytes per tet, the
  // largest allocation of a remesh at a million tets.
  auto stiffness_column = [&](int t, int b) -> Eigen::Vector4d {
    double v = 0;
    const auto g = p1_gradients_of(t, v);
    const Eigen::Matrix4d kt = (std::pow(v_max / v, options.stiffening_exponent) * v) * g * g.transpose();
    return kt.col(b);
  };
  // Free-free and free-prescribed blocks; box-boundary vertices (kind 2) never move and
  // contribute nothing.
  const VertexIncidence incidence = vertex_incidence(mesh);
  std::vector<int> free_vertex(m);
  for (int v = 0; v < n; ++v)
    if (unknown_[v] >= 0) free_vertex[unknown_[v]] = v;
  K_ff_ = gather_block_columns(mesh, incidence, is_fluid, stiffness_column, unknown_, m, free_vertex);
  K_fp_ = gather_block_columns(mesh, incidence, is_fluid, stiffness_column, unknown_, m, prescribed_);
  // CG with a diagonal preconditioner: K_ff is SPD; the tolerance is relative to the right-hand
  // side (the prescribed motion), so a rigid-body step converges to round-off.
  solver_->cg.setTolerance(options.tolerance);
  solver_->cg.setMaxIterations(std::max(1000, 4 * m));
  factorize_ = options.factorize;
  tolerance_ = options.tolerance;
  step_reduction_ = options.step_reduction;
  make_preconditioner_ = options.make_preconditioner;
  if (m > 0 && !make_preconditioner_) solver_->cg.compute(K_ff_);
  last_ = Eigen::MatrixXd::Zero(m, 3);
}

MeshMotion::~MeshMotion() = default;

std::vector<Eigen::Vector3d> MeshMotion::positions(const std::vector<Eigen::Vector3d>& solid_positions) {
  const int n = num_vertices();
  if (static_cast<int>(solid_positions.size()) != n)
    throw MeshError("mesh motion: expected " + std::to_string(n) + " positions, got " +
                    std::to_string(solid_positions.size()));
  std::vector<Eigen::Vector3d> moved = reference_;
  Eigen::MatrixXd d_p(prescribed_.size(), 3);
  for (std::size_t c = 0; c < prescribed_.size(); ++c) {
    const int v = prescribed_[c];
    moved[v] = solid_positions[v];
    d_p.row(c) = (solid_positions[v] - reference_[v]).transpose();
  }
  if (K_ff_.rows() == 0) return moved;
  // Factorize at the second call on this mesh, not the first: a mesh that is remeshed again right
  // away never pays for a factorization it uses once.
  last_iterations_ = 0;
  if (factorize_ && ++calls_ == 2) {
    solver_->cholesky.compute(K_ff_);
    solver_->factorized = solver_->cholesky.info() == Eigen::Success;
    if (solver_->factorized) precondition_ = nullptr;  // the first call's multigrid, no longer needed
  }
  const Eigen::MatrixXd rhs = -(K_fp_ * d_p);
  if (solver_->factorized) {
    last_ = solver_->cholesky.solve(rhs);
    if (solver_->cholesky.info() != Eigen::Success) throw MeshError("mesh motion: the factorized solve failed");
  }
  if (!solver_->factorized && make_preconditioner_) {
    if (!precondition_) precondition_ = make_preconditioner_(K_ff_);
    solve_preconditioned(rhs);
  }
  for (int c = 0; c < 3 && !solver_->factorized && !make_preconditioner_; ++c) {
    if (rhs.col(c).norm() == 0) {
      last_.col(c).setZero();
      continue;
    }
    last_.col(c) = solver_->cg.solveWithGuess(rhs.col(c), last_.col(c));
    if (solver_->cg.info() != Eigen::Success) throw MeshError("mesh motion: the stiffened Laplacian did not converge");
  }
  for (int v = 0; v < n; ++v)
    if (unknown_[v] >= 0) moved[v] += last_.row(unknown_[v]).transpose();
  return moved;
}

void MeshMotion::solve_preconditioned(const Eigen::MatrixXd& rhs) {
  // The initial guess extrapolates the last two solutions linearly (the solids move smoothly from
  // step to step), so a step starts a small fraction of its displacement away from the solution.
  Eigen::MatrixXd guess = last_;
  if (before_last_.size() == last_.size()) guess += last_ - before_last_;
  before_last_ = last_;
  last_iterations_ = 0;
  for (int c = 0; c < 3; ++c) {
    if (rhs.col(c).norm() == 0) {  // no motion in this component: d = 0 exactly
      last_.col(c).setZero();
      continue;
    }
    Eigen::VectorXd d = guess.col(c);
    // Stops at ‖r‖ ≤ max(tolerance ‖rhs‖, step_reduction ‖r₀‖) (MeshMotionOptions).
    Eigen::VectorXd residual = rhs.col(c) - K_ff_ * d;
    const double target = std::max(tolerance_ * rhs.col(c).norm(), step_reduction_ * residual.norm());
    // y = K_ff v column by column in parallel: K_ff is symmetric (to rounding: each entry is summed
    // in its column's order), so y_j = K_ff(:, j) · v, a gather
    // (Eigen's product scatters column by column, serially).
    auto apply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
      y.resize(v.size());
      tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(K_ff_.cols())), [&](const tbb::blocked_range<int>& columns) {
        for (int j = columns.begin(); j < columns.end(); ++j) {
          double sum = 0;
          for (Eigen::SparseMatrix<double>::InnerIterator it(K_ff_, j); it; ++it) sum += it.value() * v[it.row()];
          y[j] = sum;
        }
      });
    };
    const int iterations = preconditioned_cg(apply, precondition_, residual, d, target, max_iterations_);
    if (residual.norm() > target)
      throw MeshError("mesh motion: the stiffened Laplacian did not converge in " + std::to_string(iterations) +
                      " preconditioned CG iterations");
    last_.col(c) = d;
    last_iterations_ += iterations;
  }
}

std::vector<Eigen::Vector3d> move_with_solids(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                                              const MeshMotionOptions& options) {
  if (static_cast<int>(solid_positions.size()) != mesh.num_vertices())
    throw MeshError("mesh motion: expected " + std::to_string(mesh.num_vertices()) + " positions, got " +
                    std::to_string(solid_positions.size()));
  bool still = true;
  for (int t = 0; t < mesh.num_tets() && still; ++t)
    if (mesh.subdomain[t] != kFluidSubdomain)
      for (int v : mesh.tets[t]) still = still && solid_positions[v] == mesh.vertices[v];
  if (still) return mesh.vertices;
  return MeshMotion(mesh, options).positions(solid_positions);
}

void MeshMotion::write_state(BinaryWriter& out) const { out(last_, before_last_, calls_); }

void MeshMotion::read_state(BinaryReader& in) {
  Eigen::MatrixXd last, before_last;
  int calls = 0;
  in(last, before_last, calls);
  if (last.rows() != last_.rows() || last.cols() != last_.cols() ||
      (before_last.size() != 0 && before_last.size() != last.size()))
    in.fail("a mesh motion of another mesh");
  last_ = std::move(last);
  before_last_ = std::move(before_last);
  calls_ = calls;
  if (factorize_ && calls_ >= 2 && K_ff_.rows() > 0) {
    solver_->cholesky.compute(K_ff_);
    solver_->factorized = solver_->cholesky.info() == Eigen::Success;
  }
}

}  // namespace tetfsi::mesh
