#pragma once
/// @file follower_pressure.hpp
/// Follower pressure on boundary faces (Bonet & Wood, Nonlinear Continuum Mechanics, sec. 8.6):
/// p [Pa] pushes against the outward normal of the deformed face,
///   f_a = -p int N_a n da = -p sum_g w_g N_a (x_s x x_t),       x = X + u on the face,
/// and its consistent derivative (the load stiffness, non-symmetric on an open surface),
///   d f_a / d x_b = -p sum_g w_g N_a (N_b,t [x_s]_x - N_b,s [x_t]_x),
/// with [v]_x w = v x w. The quadrature of surface_face.hpp integrates both exactly on triangles
/// and bilinear quads (x_s x x_t is at most quadratic in s, t).
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "solid/elastic_model.hpp"
#include "solid/loads/boundary_conditions.hpp"

namespace tetfsi::solid {

/// Adds scale * f_p(u) to `force` and, if `dfdu` is not null, scale * d f_p / d u to it (its
/// pattern must hold the 3 x 3 blocks of every pair of nodes of a face, as a model's tangent does).
/// @param reference  reference positions X, 3n [m];  @param u  displacement, 3n [m]
void add_follower_pressure(const std::vector<PressureLoad>& loads, const Eigen::VectorXd& reference,
                           const Eigen::VectorXd& u, double scale, Eigen::VectorXd& force, SparseMatrix* dfdu);

/// A model with constant loads folded into its force: K_loaded(d) = K(d) - f_dead - f_p(d), and
/// K'_loaded = K' - sym(d f_p / d d), the load stiffness symmetrised (the Newmark integrator's
/// solvers need a symmetric matrix; its step is one linearised solve, so the skew part only
/// changes the step's linearisation error, not the forces). Used by the dynamic runners for
/// follower pressure; dead loads should rather go through NewmarkIntegrator::set_external_forces.
class FollowerLoadedModel : public ElasticModel {
 public:
  /// `base` must outlive this model.
  FollowerLoadedModel(const ElasticModel& base, std::vector<PressureLoad> pressures);
  int num_nodes() const override { return base_.num_nodes(); }
  const Eigen::VectorXd& reference_positions() const override { return base_.reference_positions(); }
  const Eigen::VectorXd& lumped_masses() const override { return base_.lumped_masses(); }
  bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& force, SparseMatrix* tangent) const override;
  /// The base model's strain energy (the pressure has no potential on an open surface).
  double strain_energy(const Eigen::VectorXd& d) const override { return base_.strain_energy(d); }
  std::string last_error() const override { return base_.last_error(); }
  int last_inverted_count() const override { return base_.last_inverted_count(); }

 private:
  const ElasticModel& base_;
  std::vector<PressureLoad> pressures_;
};

}  // namespace tetfsi::solid
