// Block-diagonal Cholesky over the connected components of a sparse SPD matrix (block_cholesky.hpp).
#include "coupling/solvers/block_cholesky.hpp"

#include <Eigen/CholmodSupport>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>

namespace tetfsi::coupling::detail {

struct BlockCholesky::Block {
  std::vector<int> index;  // the block's unknowns, ascending
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
  mutable Eigen::VectorXd b, x;  // gathered right-hand side and solution (one solve at a time)
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
    block.llt.factorize(num_blocks() == 1 ? A : sub_matrix(A, block.index, local_));
    ok[c] = block.llt.info() == Eigen::Success;
  });
  return std::all_of(ok.begin(), ok.end(), [](char v) { return v != 0; });
}

void BlockCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  x.resize(b.size());
  if (num_blocks() == 1) {
    x = blocks_[0]->llt.solve(b);
    return;
  }
  tbb::parallel_for(0, num_blocks(), [&](int c) {
    const Block& block = *blocks_[c];
    const int m = static_cast<int>(block.index.size());
    block.b.resize(m);
    for (int i = 0; i < m; ++i) block.b[i] = b[block.index[i]];
    block.x = block.llt.solve(block.b);
    for (int i = 0; i < m; ++i) x[block.index[i]] = block.x[i];
  });
}

}  // namespace tetfsi::coupling::detail
