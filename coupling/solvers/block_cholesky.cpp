// Block-diagonal Cholesky over the connected components of a sparse SPD matrix (block_cholesky.hpp).
#include "coupling/solvers/block_cholesky.hpp"

#include <Eigen/CholmodSupport>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "coupling/solvers/supernodal_solve.hpp"

namespace tetfsi::coupling::detail {

namespace {

/// CHOLMOD's supernodal factorization through Eigen, with its factor readable for the solves and
/// its double values freeable once copied to single precision.
class SupernodalLLT : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  /// The factor's structure (valid until the next analysis) and, if `values`, its double values
  /// (which change with each factorization).
  template <class Scalar>
  SupernodalFactorView<Scalar> factor(const Scalar* values) const {
    const cholmod_factor* L = m_cholmodFactor;
    if (!L || !L->is_super || L->itype != CHOLMOD_INT)
      throw std::logic_error("BlockCholesky: CHOLMOD returned no supernodal factor with int indices");
    SupernodalFactorView<Scalar> view;
    view.n = static_cast<int>(L->n);
    view.num_supernodes = static_cast<int>(L->nsuper);
    view.first_column = static_cast<const int*>(L->super);
    view.first_row = static_cast<const int*>(L->pi);
    view.first_value = static_cast<const int*>(L->px);
    view.row_index = static_cast<const int*>(L->s);
    view.permutation = static_cast<const int*>(L->Perm);
    view.values = values;
    return view;
  }
  /// The numeric factor in double precision.
  SupernodalFactorView<double> double_factor() const {
    if (!m_cholmodFactor || m_cholmodFactor->xtype != CHOLMOD_REAL)
      throw std::logic_error("BlockCholesky: no double precision factor (converted to single precision)");
    return factor(static_cast<const double*>(m_cholmodFactor->x));
  }
  /// Reciprocal condition number estimate of L (CHOLMOD's (min diag / max diag)²).
  double reciprocal_condition() { return cholmod_rcond(m_cholmodFactor, &cholmod()); }
  /// Copies L's values to `single` and frees the double ones: L becomes a symbolic supernodal
  /// factor, which the next factorize() fills again.
  void move_to_single_precision(std::vector<float>& single) {
    const SupernodalFactorView<double> L = double_factor();
    const int count = L.first_value[L.num_supernodes];
    single.assign(L.values, L.values + count);
    if (!cholmod_change_factor(CHOLMOD_PATTERN, /*to_ll=*/1, /*to_super=*/1, /*to_packed=*/1, /*to_monotonic=*/1,
                               m_cholmodFactor, &cholmod()) ||
        !m_cholmodFactor->is_super || m_cholmodFactor->xtype != CHOLMOD_PATTERN)
      throw std::logic_error("BlockCholesky: CHOLMOD could not free the double factor");
  }
};

}  // namespace

struct BlockCholesky::Block {
  std::vector<int> index;  // the block's unknowns, ascending
  SupernodalLLT llt;
  std::vector<float> single;  // L's values in single precision (empty: L holds them in double)
  // One solve at a time: gathered right-hand side and solution, and the solve's work vectors.
  mutable Eigen::VectorXd b, x;
  mutable SupernodalWorkspace<double> work;
  mutable SupernodalWorkspace<float> single_work;

  void solve(const double* rhs, double* solution) const {
    if (single.empty()) supernodal_solve(llt.double_factor(), rhs, solution, work);
    else supernodal_solve(llt.factor(single.data()), rhs, solution, single_work);
  }
};

BlockCholesky::BlockCholesky() = default;
BlockCholesky::~BlockCholesky() = default;

namespace {

/// Connected components of the graph of A's pattern by union-find; component of each unknown,
/// numbered by their smallest unknown (so the numbering is that of the pattern alone).
std::vector<int> components(const Eigen::SparseMatrix<double>& A, int& count) {
  const int n = static_cast<int>(A.cols());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      const int a = root(static_cast<int>(it.row())), b = root(j);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the smaller unknown stays the root
    }
  std::vector<int> component(n, -1), number(n, -1);
  count = 0;
  for (int i = 0; i < n; ++i) {
    const int r = root(i);
    if (number[r] < 0) number[r] = count++;
    component[i] = number[r];
  }
  return component;
}

}  // namespace

BlockCholesky::SparseMatrix BlockCholesky::sub_matrix(const SparseMatrix& A, const std::vector<int>& index,
                                                      const std::vector<int>& local) {
  const int m = static_cast<int>(index.size());
  SparseMatrix block(m, m);
  Eigen::Index nnz = 0;
  for (int j : index) nnz += A.outerIndexPtr()[j + 1] - A.outerIndexPtr()[j];
  block.reserve(nnz);
  // Columns in ascending global order keep each column's rows ascending in local numbering.
  for (int c = 0; c < m; ++c) {
    block.startVec(c);
    for (SparseMatrix::InnerIterator it(A, index[c]); it; ++it) block.insertBack(local[it.row()], c) = it.value();
  }
  block.finalize();
  return block;
}

void BlockCholesky::analyze_pattern(const SparseMatrix& A) {
  factorized_ = false;
  const int n = static_cast<int>(A.cols());
  int count = 0;
  const std::vector<int> component = components(A, count);
  // A component of at least 1/16 of the unknowns is a block of its own; the smaller ones (a
  // solid's pinned dofs kept as rows of their own, small bodies) share one block, so that a
  // factor is never made per handful of unknowns.
  std::vector<int> size(count, 0), block_of(count, -1);
  for (int c : component) ++size[c];
  int shared = -1, count_blocks = 0;
  for (int c = 0; c < count; ++c) {
    if (16 * size[c] >= n) block_of[c] = count_blocks++;
    else block_of[c] = shared >= 0 ? shared : (shared = count_blocks++);
  }
  blocks_.clear();
  for (int b = 0; b < count_blocks; ++b) blocks_.push_back(std::make_unique<Block>());
  local_.assign(n, -1);
  for (int i = 0; i < n; ++i) {
    Block& block = *blocks_[block_of[component[i]]];
    local_[i] = static_cast<int>(block.index.size());
    block.index.push_back(i);
  }
  count = count_blocks;
  tbb::parallel_for(0, count, [&](int c) {
    Block& block = *blocks_[c];
    block.llt.analyzePattern(count == 1 ? A : sub_matrix(A, block.index, local_));
  });
}

bool BlockCholesky::factorize(const SparseMatrix& A) {
  std::vector<char> ok(blocks_.size(), 0);
  tbb::parallel_for(0, num_blocks(), [&](int c) {
    Block& block = *blocks_[c];
    block.single = std::vector<float>();  // freed: the double values come back
    block.llt.factorize(num_blocks() == 1 ? A : sub_matrix(A, block.index, local_));
    ok[c] = block.llt.info() == Eigen::Success;
  });
  factorized_ = std::all_of(ok.begin(), ok.end(), [](char v) { return v != 0; });
  return factorized_;
}

bool BlockCholesky::to_single_precision() {
  if (!factorized_) return false;
  std::vector<char> converted(blocks_.size(), 0);
  tbb::parallel_for(0, num_blocks(), [&](int c) {
    Block& block = *blocks_[c];
    if (!block.single.empty()) {
      converted[c] = 1;
      return;
    }
    if (block.llt.reciprocal_condition() < kSingleAboveReciprocalCondition) return;
    block.llt.move_to_single_precision(block.single);
    converted[c] = 1;
  });
  return std::all_of(converted.begin(), converted.end(), [](char v) { return v != 0; });
}

void BlockCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  x.resize(b.size());
  if (num_blocks() == 1) {
    blocks_[0]->solve(b.data(), x.data());
    return;
  }
  tbb::parallel_for(0, num_blocks(), [&](int c) {
    const Block& block = *blocks_[c];
    const int m = static_cast<int>(block.index.size());
    block.b.resize(m);
    block.x.resize(m);
    for (int i = 0; i < m; ++i) block.b[i] = b[block.index[i]];
    block.solve(block.b.data(), block.x.data());
    for (int i = 0; i < m; ++i) x[block.index[i]] = block.x[i];
  });
}

}  // namespace tetfsi::coupling::detail
