#pragma once
/// @file tet_model.hpp
/// Constant-strain linear tetrahedra (Chentanez et al. 2006 sec. 3.2, O'Brien & Hodgins 1999):
/// an ElasticModel for the trapezoidal integrator.
///
/// Per tet with rest edge matrix Dm = [X1-X0, X2-X0, X3-X0] and rest volume V = det(Dm)/6:
///  - shape-function gradients g_i: rows of Dm^{-1} for i = 1..3, g_0 = -(g_1 + g_2 + g_3);
///  - F = I + sum_i d_i g_i^T (constant per tet);
///  - internal force K_i(d) = V P(F) g_i (the gradient of V Psi(F); positive where it resists);
///  - tangent K'_{ia,jc} = V [dP(e_c g_j^T) g_i]_a, the consistent Jacobian including the
///    geometric stiffness (StVK: the dF S term of constitutive.hpp).
/// Mass: lumped, rho V / 4 to each vertex.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mesh/tet_mesh.hpp"
#include "solid/assembly/block_assembler.hpp"
#include "solid/elastic_model.hpp"
#include "solid/tet/constitutive.hpp"
#include "solid/tet/material.hpp"

namespace tetfsi::solid {

struct TetModelOptions {
  /// det F at or below which an element counts as inverted/degenerate (StVK stops there).
  double min_det = 1e-6;
  /// Replace each element's material tangent dP/dF (9 x 9) by its nearest positive
  /// semi-definite matrix (negative eigenvalues clamped to zero, as in Teran et al. 2005)
  /// before assembling K'. K' is then no longer the exact Jacobian, but A = M/h + C + (h/2) K'
  /// stays positive definite under strong compression, so the Cholesky solve cannot fail.
  /// Recommended with kNeoHookeanStable for large time steps; costs a 9x9 eigensolve per tet.
  bool project_spd = false;
  /// Divergence guard: an element with |F|_2 (largest stretch, bounded by the Frobenius norm)
  /// above this stops the run with an error naming it, for every law.
  double max_stretch = 100.0;
};

class TetModel : public ElasticModel {
 public:
  /// @param mesh      rest configuration; every tet positively oriented with volume > 0
  /// @param material  one material for the whole body (validated)
  /// @param options   inversion threshold, definiteness fix
  /// @throws SolidError on an empty mesh, a degenerate or inverted rest tet, a bad material
  TetModel(const mesh::TetMesh& mesh, const TetMaterial& material, const TetModelOptions& options = {});

  int num_nodes() const override { return num_nodes_; }
  int num_tets() const { return static_cast<int>(tets_.size()); }
  const Eigen::VectorXd& reference_positions() const override { return X_; }
  const Eigen::VectorXd& lumped_masses() const override { return mass_; }
  const TetMaterial& material() const { return material_; }
  const std::vector<std::array<int, 4>>& tets() const { return tets_; }

  /// K(d) and optionally K'(d). Returns false, with last_error() naming the first such
  /// element, if an element has non-finite F, is stretched beyond options.max_stretch
  /// (diverged), or (every law but kNeoHookeanStable) has det F <= options.min_det.
  bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const override;
  /// The same force with the exact tangent dK/dd (no projection): for static Newton.
  bool evaluate_exact(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const override;
  bool modifies_tangent() const override { return options_.project_spd; }
  double strain_energy(const Eigen::VectorXd& d) const override;
  std::string last_error() const override { return last_error_; }
  int last_inverted_count() const override { return last_inverted_; }
  /// Frees the element vectors and matrices evaluate() keeps for its next call (12 doubles per tet
  /// and 144 per tet of one range of 8192), for a caller that evaluates once per step and needs the
  /// memory for the rest of it (the coupled step); the next evaluate() allocates them again.
  void release_workspace() const;

  /// Deformation gradient of tet t at displacement d.
  Eigen::Matrix3d deformation_gradient(const Eigen::VectorXd& d, int t) const;
  /// det F per tet (volume ratio).
  Eigen::VectorXd volume_ratios(const Eigen::VectorXd& d) const;
  /// Cauchy stress per tet, 6 components (xx yy zz yz xz xy) row by row, #T x 6 [Pa].
  Eigen::MatrixXd cauchy_stresses(const Eigen::VectorXd& d) const;
  /// Rest volume of tet t [m^3].
  double rest_volume(int t) const { return volume_[t]; }

 private:
  bool evaluate_with(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent, bool project) const;

  int num_nodes_ = 0;
  TetMaterial material_;
  ConstitutiveParams params_;
  TetModelOptions options_;
  std::vector<std::array<int, 4>> tets_;
  std::vector<Eigen::Matrix<double, 4, 3>> grads_;  // rows g_i^T
  std::vector<double> volume_;
  Eigen::VectorXd X_, mass_;
  BlockAssembler assembler_;
  mutable std::vector<double> element_matrices_, element_vectors_;
  mutable std::string last_error_;
  mutable int last_inverted_ = 0;
};

}  // namespace tetfsi::solid
