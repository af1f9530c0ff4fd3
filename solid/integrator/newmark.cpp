#include "solid/integrator/newmark.hpp"

#include <limits>

#include "solid/solid_error.hpp"
#include "support/stopwatch.hpp"
#include "support/number_text.hpp"

namespace tetfsi::solid {

NewmarkScheme parse_newmark_scheme(const std::string& name) {
  if (name == "chentanez") return NewmarkScheme::kChentanez;
  if (name == "trapezoidal") return NewmarkScheme::kTrapezoidal;
  throw SolidError("unknown time integration scheme '" + name + "' (expected \"chentanez\" or \"trapezoidal\")");
}

NewmarkIntegrator::NewmarkIntegrator(const ElasticModel& model, const NewmarkSettings& settings)
    : model_(model), settings_(settings), solver_(settings.solver, settings.cg_tolerance) {
  if (!(settings_.rayleigh_alpha >= 0) || !(settings_.rayleigh_beta >= 0))
    throw SolidError("solid integrator: Rayleigh alpha and beta must be >= 0");
  if (!settings_.gravity.allFinite()) throw SolidError("solid integrator: gravity must be finite");
  const int n = 3 * model_.num_nodes();
  d_.setZero(n);
  u_.setZero(n);
  f_ext_.setZero(n);
  prescribed_.setZero(n);
  fixed_.assign(n, 0);
  u_next_.setZero(n);
}

void NewmarkIntegrator::fix_nodes(const std::vector<int>& nodes, const Eigen::Vector3d& velocity) {
  fix_components(nodes, {true, true, true}, velocity);
}

void NewmarkIntegrator::fix_components(const std::vector<int>& nodes, const std::array<bool, 3>& components,
                                       const Eigen::Vector3d& velocity) {
  for (int v : nodes) {
    if (v < 0 || v >= model_.num_nodes()) throw SolidError("fix_nodes: node " + std::to_string(v) + " out of range");
    for (int a = 0; a < 3; ++a) {
      if (!components[a]) continue;
      fixed_[3 * v + a] = 1;
      prescribed_[3 * v + a] = velocity[a];
      u_[3 * v + a] = velocity[a];
    }
  }
}

std::vector<int> NewmarkIntegrator::nodes_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  std::vector<int> nodes;
  const auto& X = model_.reference_positions();
  for (int v = 0; v < model_.num_nodes(); ++v) {
    const Eigen::Vector3d x = X.segment<3>(3 * v);
    if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) nodes.push_back(v);
  }
  return nodes;
}

void NewmarkIntegrator::set_displacement(const Eigen::VectorXd& d) {
  if (d.size() != d_.size() || !d.allFinite()) throw SolidError("set_displacement: wrong size or non-finite");
  d_ = d;
}

void NewmarkIntegrator::set_velocity(const Eigen::VectorXd& u) {
  if (u.size() != u_.size() || !u.allFinite()) throw SolidError("set_velocity: wrong size or non-finite");
  for (Eigen::Index i = 0; i < u.size(); ++i) u_[i] = fixed_[i] ? prescribed_[i] : u[i];
}

void NewmarkIntegrator::set_uniform_velocity(const Eigen::Vector3d& v) {
  set_velocity(v.replicate(model_.num_nodes(), 1));
}

void NewmarkIntegrator::set_external_forces(const Eigen::VectorXd& f) {
  if (f.size() != f_ext_.size() || !f.allFinite()) throw SolidError("set_external_forces: wrong size or non-finite");
  f_ext_ = f;
}

void NewmarkIntegrator::add_spring(const LinearSpring& s) {
  if (s.node < 0 || s.node >= model_.num_nodes() || !(s.stiffness >= 0) || !s.anchor.allFinite())
    throw SolidError("add_spring: bad node index, anchor or stiffness");
  springs_.push_back(s);
}

void NewmarkIntegrator::form_system(double h, SparseMatrix& A, Eigen::VectorXd& b) {
  if (!(h > 0)) throw SolidError("solid integrator: the step h must be > 0 [s]");
  const int next = step_ + 1;
  if (!model_.evaluate(d_, K_force_, &K_tangent_))
    throw SolidError("solid step " + std::to_string(next) + " (t = " + number_text(time_) +
                     " s): " + model_.last_error());
  const auto& X = model_.reference_positions();
  for (const auto& s : springs_) {
    const Eigen::Vector3d x = X.segment<3>(3 * s.node) + d_.segment<3>(3 * s.node);
    K_force_.segment<3>(3 * s.node) += s.stiffness * (x - s.anchor);
    for (int a = 0; a < 3; ++a) K_tangent_.coeffRef(3 * s.node + a, 3 * s.node + a) += s.stiffness;
  }
  const auto& m = model_.lumped_masses();
  const double theta = settings_.scheme == NewmarkScheme::kChentanez ? 1.0 : 0.5;
  const double alpha = settings_.rayleigh_alpha, beta = settings_.rayleigh_beta;
  // b = (M/h) u - theta (h/2) K' u - (1 - theta)(alpha M + beta K') u - K(d) + M g + f_ext
  b = -(theta * 0.5 * h + (1 - theta) * beta) * (K_tangent_ * u_) - K_force_ + f_ext_;
  // A = (1/h + theta alpha) M + theta (beta + h/2) K', made in K''s storage (K' is not needed
  // after this; the next evaluate() refills whatever matrix K_tangent_ then holds): one copy of
  // the pattern per solid instead of two.
  A.swap(K_tangent_);
  A *= theta * (beta + 0.5 * h);
  const double mass_coef = 1.0 / h + theta * alpha;
  for (int v = 0; v < model_.num_nodes(); ++v)
    for (int a = 0; a < 3; ++a) A.coeffRef(3 * v + a, 3 * v + a) += mass_coef * m[v];
  const double mass_u_coef = 1.0 / h - (1 - theta) * alpha;
  for (int v = 0; v < model_.num_nodes(); ++v)
    b.segment<3>(3 * v) += m[v] * (mass_u_coef * u_.segment<3>(3 * v) + settings_.gravity);
  // Symmetric elimination of Dirichlet DOFs.
  for (int col = 0; col < A.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(A, col); it; ++it) {
      const int row = static_cast<int>(it.row());
      if (!fixed_[col] && !fixed_[row]) continue;
      if (row == col) {
        b[row] = it.value() * prescribed_[row];
      } else {
        if (fixed_[col] && !fixed_[row]) b[row] -= it.value() * prescribed_[col];
        it.valueRef() = 0.0;
      }
    }
  stats_.inverted = model_.last_inverted_count();
}

Eigen::VectorXd NewmarkIntegrator::end_displacement(double h, const Eigen::VectorXd& u_next) const {
  return d_ + 0.5 * h * (u_ + u_next);
}

void NewmarkIntegrator::advance(double h, const Eigen::VectorXd& u_next) {
  const int next = step_ + 1;
  if (u_next.size() != u_.size()) throw SolidError("advance: velocity has the wrong size");
  for (Eigen::Index i = 0; i < u_next.size(); ++i)
    if (!std::isfinite(u_next[i]))
      throw SolidError("solid step " + std::to_string(next) + ": non-finite velocity at node " +
                       std::to_string(i / 3) + " (diverged)");
  d_ = end_displacement(h, u_next);  // eq. (5), contact nodes landing on their obstacle
  u_ = u_next;
  for (Eigen::Index i = 0; i < u_.size(); ++i)
    if (fixed_[i]) u_[i] = prescribed_[i];
  // Contacts of the implicit solve: inelastic normal (friction was part of the solve).
  contact_force_.setZero();
  for (const auto& c : active_) {
    Eigen::Vector3d vel = u_.segment<3>(3 * c.node);
    u_.segment<3>(3 * c.node) = vel - vel.dot(c.normal) * c.normal;
    contact_force_ += std::max(0.0, c.force) * c.normal;
  }
  const int solved_contacts = static_cast<int>(active_.size());
  last_contact_nodes_.clear();
  last_contact_forces_.clear();
  for (const auto& c : active_) last_contact_nodes_.push_back(c.node), last_contact_forces_.push_back(c.force);
  active_.clear();
  stats_.contacts = std::max(solved_contacts, obstacles_.project(model_.reference_positions(), d_, u_, fixed_)) +
                    (self_contact_ ? self_contact_->num_active() : 0);
  ++step_;
  time_ += h;
}

const StepStats& NewmarkIntegrator::step(double h) {
  const Stopwatch clock;
  form_system(h, A_, b_);
  const double assembly = clock.seconds();
  u_next_ = u_;
  solve_with_contact(h, "solid step " + std::to_string(step_ + 1));
  const double solve_seconds = clock.seconds() - assembly;
  advance(h, u_next_);
  const int inverted = stats_.inverted, contacts = stats_.contacts;
  if (settings_.track_energy) stats_ = energies();
  stats_.step = step_;
  stats_.time = time_;
  stats_.assembly_seconds = assembly;
  stats_.solve_seconds = solve_seconds;
  stats_.solver_iterations = solver_.last_stats().iterations;
  stats_.inverted = inverted;
  stats_.contacts = contacts;
  return stats_;
}

void NewmarkIntegrator::solve_with_contact(double h, const std::string& context) {
  active_.clear();
  const bool self = self_contact_ && self_contact_->enabled();
  if (self) self_contact_->begin_step(h, positions(), u_, fixed_);
  if (obstacles_.empty() && !self) {
    solver_.solve(A_, b_, u_next_, context);
    return;
  }
  const SparseMatrix A_free = A_;
  const Eigen::VectorXd b_free = b_;
  const auto with_contact_rows = [&] {
    A_ = A_free;
    b_ = b_free;
    add_contact_rows(A_, b_);
    if (self) self_contact_->add_rows(A_, b_);
  };
  if (self && self_contact_->warm_start()) with_contact_rows();
  solver_.solve(A_, b_, u_next_, context);
  for (int round = 0; round < 8; ++round) {
    bool changed = update_contacts(h, u_next_);
    if (self) changed = self_contact_->update(u_next_) || changed;
    if (!changed) break;
    with_contact_rows();
    solver_.solve(A_, b_, u_next_, context);
  }
  finish_contacts(u_next_);
  if (self) self_contact_->finish(u_next_);  // forces, then friction on u^{n+1}
}

void NewmarkIntegrator::enable_self_contact(const std::vector<std::array<int, 4>>& tets, double gap, double friction) {
  SurfaceContactSettings settings;
  settings.gap = gap;
  settings.friction = friction;
  settings.penalty = settings_.contact_penalty;
  self_contact_ = std::make_unique<SurfaceContact>(settings);
  self_contact_->add_solid(tets, model_.reference_positions(), model_.lumped_masses(), 0, true);
}

double NewmarkIntegrator::friction_damping(double force, const Eigen::Vector3d& normal,
                                           const Eigen::Vector3d& velocity) const {
  const double mu = obstacles_.friction();
  if (!(mu > 0) || !(force > 0)) return 0.0;
  const double slip = (velocity - velocity.dot(normal) * normal).norm();
  return mu * force / std::max(slip, settings_.friction_velocity);
}

void NewmarkIntegrator::activate_contact(int v, double h, const Eigen::Vector3d& normal, double force) {
  const Eigen::Vector3d x0 = model_.reference_positions().segment<3>(3 * v) + d_.segment<3>(3 * v);
  Eigen::Vector3d n0;
  const double phi0 = std::max(0.0, obstacles_.signed_distance(x0, n0));
  // κ from the node's inertia m/h, not A's diagonal: a stiff solid's (h/2) K′ term made κ n nᵀ
  // (for a normal off the axes, spread over the 3 x 3 block) so large that the coupled solve
  // stalled at a fluid residual of 2e-7 against 1e-8 (a ball of E = 1e8 Pa in a spherical tank).
  const double kappa = settings_.contact_penalty * model_.lumped_masses()[v] / h;
  const Eigen::Vector3d un = u_.segment<3>(3 * v);
  active_.push_back({v, normal, -2.0 * phi0 / h - normal.dot(un), kappa, force, friction_damping(force, normal, un)});
}

bool NewmarkIntegrator::warm_start_contacts(double h) {
  active_.clear();
  if (obstacles_.empty()) return false;
  const auto& X = model_.reference_positions();
  for (std::size_t k = 0; k < last_contact_nodes_.size(); ++k) {
    const int v = last_contact_nodes_[k];
    Eigen::Vector3d normal;
    // Still touching (within a thousandth of the step's travel at 1 mm/s, or closer).
    if (obstacles_.signed_distance(X.segment<3>(3 * v) + d_.segment<3>(3 * v), normal) > 1e-6 * h) continue;
    activate_contact(v, h, normal, k < last_contact_forces_.size() ? last_contact_forces_[k] : 0.0);
  }
  return !active_.empty();
}

bool NewmarkIntegrator::update_contacts(double h, const Eigen::VectorXd& u_next,
                                        int offset) {
  if (obstacles_.empty()) return false;
  bool changed = false;
  const int n = model_.num_nodes();
  std::vector<char> is_active(n, 0);
  // Release pulling constraints.
  for (size_t k = 0; k < active_.size();) {
    auto& c = active_[k];
    const Eigen::Vector3d velocity = u_next.segment<3>(offset + 3 * c.node);
    c.force = c.kappa * (c.target - c.normal.dot(velocity));
    // The friction for the next round's solve; a change of more than 1% is solved again.
    const double friction = friction_damping(c.force, c.normal, velocity);
    changed = changed || std::abs(friction - c.friction) > kFrictionChange * std::max(friction, c.friction);
    c.friction = friction;
    if (c.force < 0) {
      active_[k] = active_.back();
      active_.pop_back();
      changed = true;
    } else {
      is_active[c.node] = 1;
      ++k;
    }
  }
  // Activate nodes that would end inside an obstacle.
  const auto& X = model_.reference_positions();
  for (int v = 0; v < n; ++v) {
    if (is_active[v] || fixed_[3 * v] || fixed_[3 * v + 1] || fixed_[3 * v + 2]) continue;
    const Eigen::Vector3d x0 = X.segment<3>(3 * v) + d_.segment<3>(3 * v);
    const Eigen::Vector3d x1 = x0 + 0.5 * h * (u_.segment<3>(3 * v) + u_next.segment<3>(offset + 3 * v));
    Eigen::Vector3d normal;
    if (!(obstacles_.signed_distance(x1, normal) < 0)) continue;
    activate_contact(v, h, normal);
    changed = true;
  }
  return changed;
}

void NewmarkIntegrator::add_contact_rows(SparseMatrix& A, Eigen::VectorXd& b, int offset) const {
  for (const auto& c : active_) {
    const Eigen::Matrix3d nn = c.normal * c.normal.transpose();
    const Eigen::Matrix3d P = c.kappa * nn + c.friction * (Eigen::Matrix3d::Identity() - nn);
    const int r = offset + 3 * c.node;
    for (int a = 0; a < 3; ++a) {
      b[r + a] += c.kappa * c.target * c.normal[a];
      for (int k = 0; k < 3; ++k) A.coeffRef(r + a, r + k) += P(a, k);
    }
  }
}

void NewmarkIntegrator::finish_contacts(const Eigen::VectorXd& u_next, int offset) {
  for (auto& c : active_) c.force = c.kappa * (c.target - c.normal.dot(u_next.segment<3>(offset + 3 * c.node)));
}

double NewmarkIntegrator::obstacle_clearance() const {
  double clearance = std::numeric_limits<double>::infinity();
  if (obstacles_.empty()) return clearance;
  const auto& X = model_.reference_positions();
  Eigen::Vector3d normal;
  for (int v = 0; v < model_.num_nodes(); ++v)
    clearance = std::min(clearance, obstacles_.signed_distance(X.segment<3>(3 * v) + d_.segment<3>(3 * v), normal));
  return clearance;
}

StepStats NewmarkIntegrator::energies() const {
  StepStats s;
  const auto& m = model_.lumped_masses();
  const auto& X = model_.reference_positions();
  for (int v = 0; v < model_.num_nodes(); ++v) {
    s.kinetic += 0.5 * m[v] * u_.segment<3>(3 * v).squaredNorm();
    s.gravity_potential -= m[v] * settings_.gravity.dot(X.segment<3>(3 * v) + d_.segment<3>(3 * v));
  }
  for (const auto& sp : springs_)
    s.spring += 0.5 * sp.stiffness * (X.segment<3>(3 * sp.node) + d_.segment<3>(3 * sp.node) - sp.anchor).squaredNorm();
  s.strain = model_.strain_energy(d_);
  s.step = step_;
  s.time = time_;
  return s;
}

}  // namespace tetfsi::solid
