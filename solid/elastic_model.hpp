#pragma once
/// @file elastic_model.hpp
/// The interface between a spatial discretization of an elastic body (tet FEM, Total
/// Lagrangian hex8, ...) and the time integrator of Chentanez et al. 2006, appendix (eqs. 9-18).
///
/// Eq. (3): M a + C(u, d) + K(d) - f_p - f_e = 0. A model provides, at a displacement d:
///  - M, the lumped nodal masses (one per node, the same for its x, y, z rows);
///  - K(d), the internal elastic force vector (positive where it resists the deformation);
///  - K'(d) = dK/dd, its Jacobian (the tangent stiffness), sparse and symmetric.
/// Degrees of freedom are ordered node by node: [x0 y0 z0 x1 y1 z1 ...].
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace tetfsi::solid {

using SparseMatrix = Eigen::SparseMatrix<double>;

class ElasticModel {
 public:
  virtual ~ElasticModel() = default;

  /// Number of nodes; the model has 3 * num_nodes() degrees of freedom.
  virtual int num_nodes() const = 0;

  /// Reference (undeformed) positions X, size 3 * num_nodes() [m].
  virtual const Eigen::VectorXd& reference_positions() const = 0;

  /// Lumped nodal masses, size num_nodes() [kg].
  virtual const Eigen::VectorXd& lumped_masses() const = 0;

  /// Evaluates the internal force K(d) [N] and, if `tangent` is not null, K'(d) [N/m].
  /// @param d        displacement, size 3 * num_nodes() [m]
  /// @param force    out: K(d), size 3 * num_nodes()
  /// @param tangent  out (optional): dK/dd at d, 3n x 3n, symmetric
  /// @return false if an element is inverted or degenerate at d and the model cannot handle it
  virtual bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force,
                        SparseMatrix* tangent) const = 0;

  /// True if evaluate() assembles a modified tangent instead of dK/dd (e.g. TetModelOptions::project_spd,
  /// kept positive semi-definite per element for the dynamic step).
  virtual bool modifies_tangent() const { return false; }

  /// evaluate() with the exact tangent dK/dd even where evaluate() modifies it; static Newton uses it
  /// wherever the assembled system is positive definite (quadratic convergence).
  virtual bool evaluate_exact(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const {
    return evaluate(d, force, tangent);
  }

  /// Elastic (strain) energy at d [J].
  virtual double strain_energy(const Eigen::VectorXd& d) const = 0;

  /// Why the last evaluate() returned false (names the element and the cause); empty if it
  /// succeeded. Optional for implementations.
  virtual std::string last_error() const { return {}; }

  /// Number of inverted elements (det F <= 0) seen by the last evaluate() that the model
  /// handled (inversion-robust laws); 0 for models that never report it.
  virtual int last_inverted_count() const { return 0; }
};

}  // namespace tetfsi::solid
