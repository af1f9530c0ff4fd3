#include "solid/assembly/block_assembler.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "mesh/incidence.hpp"
#include "solid/solid_error.hpp"

namespace tetfsi::solid {

BlockAssembler::BlockAssembler(int num_nodes, int nodes_per_element, const std::vector<int>& elements)
    : num_nodes_(num_nodes), npe_(nodes_per_element), elements_(elements) {
  if (npe_ <= 0 || elements_.size() % npe_ != 0)
    throw SolidError("BlockAssembler: element array size is not a multiple of nodes_per_element");
  num_elements_ = static_cast<int>(elements_.size() / npe_);
  for (int v : elements_)
    if (v < 0 || v >= num_nodes_) throw SolidError("BlockAssembler: element node index out of range");

  // Incidence lists (counting sort keeps element order).
  mesh::VertexIncidence inc = mesh::vertex_incidence(num_nodes_, npe_, elements_);
  incident_start_ = std::move(inc.start);
  incident_element_ = std::move(inc.element);
  incident_local_ = std::move(inc.local);

  // Node adjacency (sorted, unique) -> block column pattern.
  std::vector<std::vector<int>> adj(num_nodes_);
  for (int v = 0; v < num_nodes_; ++v) {
    auto& a = adj[v];
    for (int k = incident_start_[v]; k < incident_start_[v + 1]; ++k) {
      const int e = incident_element_[k];
      for (int i = 0; i < npe_; ++i) a.push_back(elements_[e * npe_ + i]);
    }
    if (a.empty()) a.push_back(v);  // isolated node: keep a diagonal block
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  const int n = 3 * num_nodes_;
  pattern_.resize(n, n);
  std::vector<int> col_nnz(n);
  for (int v = 0; v < num_nodes_; ++v)
    for (int c = 0; c < 3; ++c) col_nnz[3 * v + c] = 3 * static_cast<int>(adj[v].size());
  pattern_.reserve(col_nnz);
  for (int v = 0; v < num_nodes_; ++v)
    for (int c = 0; c < 3; ++c)
      for (int u : adj[v])
        for (int a = 0; a < 3; ++a) pattern_.insert(3 * u + a, 3 * v + c) = 0.0;
  pattern_.makeCompressed();

  // Offsets of element blocks: position of node n_i in adj[n_j], times 3.
  block_offset_.resize(static_cast<size_t>(num_elements_) * npe_ * npe_);
  for (int e = 0; e < num_elements_; ++e)
    for (int j = 0; j < npe_; ++j) {
      const auto& a = adj[elements_[e * npe_ + j]];
      for (int i = 0; i < npe_; ++i) {
        const int ni = elements_[e * npe_ + i];
        const int pos = static_cast<int>(std::lower_bound(a.begin(), a.end(), ni) - a.begin());
        block_offset_[(static_cast<size_t>(e) * npe_ + j) * npe_ + i] = 3 * pos;
      }
    }
}

void BlockAssembler::assemble_matrix(const std::vector<double>& ke, Eigen::SparseMatrix<double>& out) const {
  const int nd = 3 * npe_;
  if (ke.size() != static_cast<size_t>(num_elements_) * nd * nd)
    throw SolidError("BlockAssembler: element matrix buffer has the wrong size");
  if (out.rows() != pattern_.rows() || out.nonZeros() != pattern_.nonZeros() || !out.isCompressed())
    out = pattern_;
  double* values = out.valuePtr();
  const auto* outer = out.outerIndexPtr();
  tbb::parallel_for(0, num_nodes_, [&](int v) {
    for (int c = 0; c < 3; ++c) {
      const int col = 3 * v + c;
      std::fill(values + outer[col], values + outer[col + 1], 0.0);
    }
    for (int k = incident_start_[v]; k < incident_start_[v + 1]; ++k) {
      const int e = incident_element_[k];
      const int j = incident_local_[k];
      const double* K = ke.data() + static_cast<size_t>(e) * nd * nd;
      const int* off = block_offset_.data() + (static_cast<size_t>(e) * npe_ + j) * npe_;
      for (int c = 0; c < 3; ++c) {
        const int col = 3 * v + c;
        const double* kcol = K + static_cast<size_t>(3 * j + c) * nd;
        for (int i = 0; i < npe_; ++i) {
          double* dst = values + outer[col] + off[i];
          for (int a = 0; a < 3; ++a) dst[a] += kcol[3 * i + a];
        }
      }
    }
  });
}

void BlockAssembler::assemble_vector(const std::vector<double>& fe, Eigen::VectorXd& out) const {
  const int nd = 3 * npe_;
  if (fe.size() != static_cast<size_t>(num_elements_) * nd)
    throw SolidError("BlockAssembler: element vector buffer has the wrong size");
  out.setZero(3 * num_nodes_);
  tbb::parallel_for(0, num_nodes_, [&](int v) {
    for (int k = incident_start_[v]; k < incident_start_[v + 1]; ++k) {
      const double* f = fe.data() + static_cast<size_t>(incident_element_[k]) * nd + 3 * incident_local_[k];
      for (int a = 0; a < 3; ++a) out[3 * v + a] += f[a];
    }
  });
}

}  // namespace tetfsi::solid
