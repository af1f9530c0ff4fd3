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
  pattern_outer_.assign(n + 1, 0);
  for (int v = 0; v < num_nodes_; ++v)
    for (int c = 0; c < 3; ++c) pattern_outer_[3 * v + c + 1] = pattern_outer_[3 * v + c] + 3 * static_cast<int>(adj[v].size());
  pattern_inner_.resize(pattern_outer_[n]);
  for (int v = 0; v < num_nodes_; ++v)
    for (int c = 0; c < 3; ++c) {
      int* rows = pattern_inner_.data() + pattern_outer_[3 * v + c];
      for (int u : adj[v])
        for (int a = 0; a < 3; ++a) *rows++ = 3 * u + a;
    }

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

void BlockAssembler::add_element_matrices(const double* ke, int first, int end, Eigen::SparseMatrix<double>& out) const {
  const int nd = 3 * npe_;
  if (first < 0 || end > num_elements_ || first > end)
    throw SolidError("BlockAssembler: element range outside the mesh");
  const int n = 3 * num_nodes_;
  const auto nnz = static_cast<Eigen::Index>(pattern_inner_.size());
  if (first == 0 && (out.rows() != n || out.cols() != n || out.nonZeros() != nnz || !out.isCompressed())) {
    out.resize(n, n);  // compressed, no entries
    out.resizeNonZeros(nnz);
    std::copy(pattern_outer_.begin(), pattern_outer_.end(), out.outerIndexPtr());
    std::copy(pattern_inner_.begin(), pattern_inner_.end(), out.innerIndexPtr());  // values: zeroed below
  }
  double* values = out.valuePtr();
  const auto* outer = out.outerIndexPtr();
  tbb::parallel_for(0, num_nodes_, [&](int v) {
    if (first == 0)
      for (int c = 0; c < 3; ++c) {
        const int col = 3 * v + c;
        std::fill(values + outer[col], values + outer[col + 1], 0.0);
      }
    // The node's incident elements are sorted: those in [first, end) are one run of them.
    const int* incident = incident_element_.data();
    const int* last = incident + incident_start_[v + 1];
    const int lo = static_cast<int>(std::lower_bound(incident + incident_start_[v], last, first) - incident);
    const int hi = static_cast<int>(std::lower_bound(incident + lo, last, end) - incident);
    for (int k = lo; k < hi; ++k) {
      const int e = incident_element_[k];
      const int j = incident_local_[k];
      const double* K = ke + static_cast<size_t>(e - first) * nd * nd;
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
