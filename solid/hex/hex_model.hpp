#pragma once
/// @file hex_model.hpp
/// A body of Total Lagrangian hex8 elements (hex8_element.hpp) assembled into global vectors and
/// the sparse tangent, behind the ElasticModel interface, so that the trapezoidal integrator of
/// the tet solid (Chentanez et al. 2006, appendix eqs. 9-18) runs it unchanged:
///   K(d)  = F_int(d) = sum_e int B_L^T S dV,   K'(d) = K_T(d) = sum_e (K_L + K_NL),
///   M_a   = sum_e int rho N_a dV  (row-sum lumping of the consistent mass; > 0 for trilinear hexes).
///
/// Assembly is parallel with TBB and deterministic: elements are greedily coloured so that no two
/// elements of a colour share a node; colours run one after another, the elements of a colour in
/// parallel, each adding into the nodes it owns alone in that colour. Every global entry therefore
/// receives its contributions in the same (colour) order whatever the thread count.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "mesh/hex_mesh.hpp"
#include "solid/elastic_model.hpp"
#include "solid/hex/hex8_element.hpp"
#include "solid/hex/hex8_enhanced.hpp"
#include "solid/hex/material.hpp"

namespace tetfsi::solid::hex {

class HexModel : public ElasticModel {
 public:
  /// @throws std::invalid_argument for an empty mesh, an out-of-range or repeated node index,
  ///         an element with det J <= 0 at a Gauss point (wrong node order), or a bad material
  /// `formulation`: the element (hex8_element.hpp, hex8_enhanced.hpp); enhanced by default.
  HexModel(mesh::HexMesh mesh, Material material, Hex8Formulation formulation = Hex8Formulation::Enhanced);

  int num_nodes() const override { return mesh_.num_vertices(); }
  const Eigen::VectorXd& reference_positions() const override { return reference_; }
  const Eigen::VectorXd& lumped_masses() const override { return masses_; }
  /// F_int(d) and K_T(d). Returns false (outputs unspecified) if d has a non-finite entry or an
  /// element is inverted (det F <= 0 at a Gauss point); last_failed_element() then names it.
  bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const override;
  /// int psi dV [J]; +infinity if an element is inverted.
  double strain_energy(const Eigen::VectorXd& d) const override;

  const mesh::HexMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  Hex8Formulation formulation() const { return formulation_; }
  /// The (full, symmetric) sparsity pattern of K_T with zero values.
  const SparseMatrix& pattern() const { return pattern_; }
  int num_colors() const { return static_cast<int>(colors_.size()); }
  /// Element that made the last evaluate() fail, or -1.
  int last_failed_element() const { return failed_element_; }
  /// Why the last evaluate() failed, naming the element: "" after a success.
  std::string last_error() const override;
  /// Elements that are inverted or degenerate at `d` (det F <= 0 or det J <= 0 at a Gauss point),
  /// in increasing order; every element if `d` has a non-finite entry.
  std::vector<int> failed_elements(const Eigen::VectorXd& d) const;

  /// Element-averaged Cauchy and 2nd Piola-Kirchhoff stresses [Pa], 6 Voigt values per element
  /// [xx yy zz xy yz zx]; NaN for an inverted element.
  void element_stresses(const Eigen::VectorXd& d, std::vector<double>& cauchy, std::vector<double>& pk2) const;

 private:
  Matrix83d element_positions(int e) const;
  Matrix83d element_displacements(int e, const Eigen::VectorXd& d) const;
  /// The element of `formulation_` at d (hex8_evaluate or hex8_enhanced_evaluate).
  ElementStatus evaluate_element(int e, const Eigen::VectorXd& d, Vector24d* f, Matrix24d* K, double* energy) const;

  mesh::HexMesh mesh_;
  Material material_;
  Hex8Formulation formulation_;
  Eigen::VectorXd reference_;
  Eigen::VectorXd masses_;
  std::vector<std::vector<int>> colors_;  ///< element ids per colour
  SparseMatrix pattern_;
  /// For element e and local nodes (a, b): offset of row 3 * node_a inside column 3 * node_b + l
  /// (the same for l = 0, 1, 2), 64 entries per element, index a + 8 b.
  std::vector<int> block_offsets_;
  mutable int failed_element_ = -1;
  mutable bool failed_non_finite_ = false;  ///< the last evaluate() got a non-finite d
};

}  // namespace tetfsi::solid::hex
