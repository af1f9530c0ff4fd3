#pragma once
/// @file block_assembler.hpp
/// Deterministic, TBB-parallel assembly of element matrices and vectors into a fixed sparse
/// pattern, for any element with `nodes_per_element` nodes and 3 DOFs per node.
///
/// The pattern (3x3 blocks for every pair of nodes sharing an element) is built once. Each
/// element's (i, j) block has a precomputed offset in the column storage, and assembly runs
/// in parallel over node columns, summing the incident elements in increasing element order.
/// Every entry is therefore the same floating-point sum whatever the thread count (a plain
/// setFromTriplets per step would also be deterministic, but sorts ~144 triplets per tet).
#include <Eigen/SparseCore>
#include <vector>

namespace tetfsi::solid {

class BlockAssembler {
 public:
  BlockAssembler() = default;
  /// @param num_nodes          number of nodes (matrix size 3 num_nodes)
  /// @param nodes_per_element  e.g. 4 for tets, 8 for hexes
  /// @param elements           flat node indices, nodes_per_element per element
  BlockAssembler(int num_nodes, int nodes_per_element, const std::vector<int>& elements);

  int num_nodes() const { return num_nodes_; }
  int num_elements() const { return num_elements_; }
  int element_dofs() const { return 3 * npe_; }

  /// out = sum_e P_e^T K_e P_e over the elements [first, end), added to out (first == 0: out is
  /// first given the pattern, 3x3 blocks for every pair of nodes sharing an element, 3n x 3n,
  /// compressed, rows sorted, if it does not have it, and set to zero). `element_matrices` holds
  /// (3 npe)^2 doubles per element of the range, from element `first` on, each column major over
  /// local DOFs [3 i + a]. Called for consecutive ranges 0 = e_0 < e_1 < ... < e_k = num_elements(),
  /// every entry is the same floating-point sum, in increasing element order, as one call over all
  /// elements, while only one range's element matrices are held at a time.
  void add_element_matrices(const double* element_matrices, int first, int end, Eigen::SparseMatrix<double>& out) const;

  /// out = sum_e P_e^T f_e; `element_vectors` holds 3 npe doubles per element.
  void assemble_vector(const std::vector<double>& element_vectors, Eigen::VectorXd& out) const;

 private:
  int num_nodes_ = 0;
  int npe_ = 0;
  int num_elements_ = 0;
  std::vector<int> elements_;
  // The pattern (3n x 3n, column major, rows sorted) as compressed column indices only; the
  // matrices themselves are assembled into the caller's storage.
  std::vector<int> pattern_outer_, pattern_inner_;
  // Node -> incident (element, local index), CSR, sorted by element.
  std::vector<int> incident_start_;
  std::vector<int> incident_element_;
  std::vector<int> incident_local_;
  // Per element, per (i local row node, j local column node): offset of row 3 n_i inside
  // column 3 n_j (same for the node's three columns).
  std::vector<int> block_offset_;
};

}  // namespace tetfsi::solid
