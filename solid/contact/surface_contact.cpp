/// @file surface_contact.cpp
/// SurfaceContact (surface_contact.hpp): candidate search, active set, penalty rows, friction.
#include "solid/contact/surface_contact.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <unordered_map>

#include "solid/contact/closest_point.hpp"

namespace tetfsi::solid {
namespace {

/// The tets' boundary triangles (faces of one tet only), oriented away from the tet's fourth node.
std::vector<std::array<int, 3>> boundary_triangles(const std::vector<std::array<int, 4>>& tets,
                                                   const Eigen::VectorXd& X) {
  static constexpr int kFace[4][4] = {{1, 2, 3, 0}, {0, 3, 2, 1}, {0, 1, 3, 2}, {0, 2, 1, 3}};
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 4>>> faces;  // sorted face -> count, (i, j, k, opposite)
  for (const auto& t : tets)
    for (const auto& f : kFace) {
      std::array<int, 3> key = {t[f[0]], t[f[1]], t[f[2]]};
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      ++entry.first;
      entry.second = {t[f[0]], t[f[1]], t[f[2]], t[f[3]]};
    }
  std::vector<std::array<int, 3>> out;
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1) continue;
    auto [i, j, k, l] = entry.second;
    const Eigen::Vector3d xi = X.segment<3>(3 * i);
    if ((X.segment<3>(3 * j) - xi).cross(X.segment<3>(3 * k) - xi).dot(X.segment<3>(3 * l) - xi) > 0) std::swap(j, k);
    out.push_back({i, j, k});
  }
  return out;
}

Eigen::Vector3d node_at(const Eigen::VectorXd& x, int v) { return x.segment<3>(3 * v); }

/// Uniform hash grid of boxes (cell size `cell`): the boxes overlapping a point's cell.
class BoxGrid {
 public:
  explicit BoxGrid(double cell) : cell_(cell) {}
  void insert(int id, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const Eigen::Vector3i a = index(lo), b = index(hi);
    for (int i = a.x(); i <= b.x(); ++i)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int k = a.z(); k <= b.z(); ++k) cells_[key({i, j, k})].push_back(id);
  }
  const std::vector<int>& at(const Eigen::Vector3d& x) const {
    static const std::vector<int> kNone;
    const auto it = cells_.find(key(index(x)));
    return it == cells_.end() ? kNone : it->second;
  }

 private:
  Eigen::Vector3i index(const Eigen::Vector3d& x) const { return (x / cell_).array().floor().cast<int>(); }
  static long long key(const Eigen::Vector3i& c) {
    return (static_cast<long long>(c.x() & 0x1FFFFF) << 42) | (static_cast<long long>(c.y() & 0x1FFFFF) << 21) |
           static_cast<long long>(c.z() & 0x1FFFFF);
  }
  double cell_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace

SurfaceContact::SurfaceContact(SurfaceContactSettings settings) : settings_(settings) {
  if (!(settings_.gap >= 0)) throw std::invalid_argument("surface contact: the gap must be >= 0");
  if (!(settings_.penalty > 0)) throw std::invalid_argument("surface contact: the penalty must be > 0");
  if (!(settings_.friction >= 0)) throw std::invalid_argument("surface contact: the friction must be >= 0");
}

void SurfaceContact::add_solid(const std::vector<std::array<int, 4>>& tets, const Eigen::VectorXd& X,
                               const Eigen::VectorXd& masses, int dof_offset, bool self_contact) {
  if (dof_offset % 3 != 0 || dof_offset != X_.size() || X.size() != 3 * masses.size())
    throw std::invalid_argument("surface contact: solids must be added in dof order with 3 dofs per node");
  const int first = dof_offset / 3, n = static_cast<int>(masses.size());
  X_.conservativeResize(X_.size() + X.size());
  X_.tail(X.size()) = X;
  mass_.conservativeResize(mass_.size() + n);
  mass_.tail(n) = masses;
  node_solid_.resize(first + n, num_solids_);
  node_triangles_.resize(first + n);
  std::vector<char> on_surface(n, 0);
  for (const auto& t : boundary_triangles(tets, X)) {
    const int id = static_cast<int>(triangles_.size());
    triangles_.push_back({{first + t[0], first + t[1], first + t[2]}, num_solids_});
    for (int v : t) on_surface[v] = 1, node_triangles_[first + v].push_back(id);
  }
  for (int v = 0; v < n; ++v)
    if (on_surface[v]) surface_node_.push_back(first + v);
  self_contact_.push_back(self_contact);
  ++num_solids_;
}

bool SurfaceContact::enabled() const {
  return (settings_.between_solids && num_solids_ > 1) ||
         std::any_of(self_contact_.begin(), self_contact_.end(), [](char c) { return c != 0; });
}

void SurfaceContact::begin_step(double h, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                                const std::vector<char>& prescribed) {
  h_ = h;
  prescribed_ = prescribed;
  u_start_ = u;
  candidates_.clear();
  active_.clear();
  if (!enabled() || triangles_.empty()) return;
  // Reach: a node within this distance of a triangle may close the gap δ in the step (speeds up
  // to twice the largest surface speed at tⁿ).
  double v_max = 0, edge_sum = 0;
  for (int v : surface_node_) v_max = std::max(v_max, node_at(u, v).norm());
  std::vector<Eigen::Vector3d> face_normal(triangles_.size());
  std::vector<Eigen::Vector3d> node_normal(X_.size() / 3, Eigen::Vector3d::Zero());
  for (size_t f = 0; f < triangles_.size(); ++f) {
    const auto& t = triangles_[f].node;
    const Eigen::Vector3d a = node_at(x, t[0]), b = node_at(x, t[1]), c = node_at(x, t[2]);
    const Eigen::Vector3d area_normal = (b - a).cross(c - a);
    face_normal[f] = area_normal.normalized();
    for (int v : t) node_normal[v] += area_normal;
    edge_sum += (b - a).norm() + (c - b).norm() + (a - c).norm();
  }
  const double cell = edge_sum / (3.0 * static_cast<double>(triangles_.size()));
  const double reach = 2 * settings_.gap + 4 * h * v_max;
  const double rest_margin = std::max(2 * settings_.gap, 0.5 * cell);
  BoxGrid grid(std::max(cell, reach));
  for (size_t f = 0; f < triangles_.size(); ++f) {
    const auto& t = triangles_[f].node;
    Eigen::Vector3d lo = node_at(x, t[0]), hi = lo;
    for (int m = 1; m < 3; ++m) lo = lo.cwiseMin(node_at(x, t[m])), hi = hi.cwiseMax(node_at(x, t[m]));
    grid.insert(static_cast<int>(f), lo.array() - reach, hi.array() + reach);
  }
  for (int a : surface_node_) {
    if (node_prescribed(a)) continue;
    const Eigen::Vector3d xa = node_at(x, a);
    Pair best{a, -1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0, 0};
    double best_distance = reach + settings_.gap;
    for (int f : grid.at(xa)) {
      const Triangle& tri = triangles_[f];
      const bool same = tri.solid == node_solid_[a];
      if (same ? !self_contact_[tri.solid] : !settings_.between_solids) continue;
      const auto& t = tri.node;
      if (same) {
        if (t[0] == a || t[1] == a || t[2] == a) continue;
        if (face_normal[f].dot(node_normal[a].normalized()) > -0.5) continue;
        const Eigen::Vector3d A0 = node_at(X_, t[0]), B0 = node_at(X_, t[1]), C0 = node_at(X_, t[2]);
        const ClosestPoint rest = closest_point_on_triangle(node_at(X_, a), A0, B0, C0);
        if (rest.distance < rest_margin) continue;
        // At rest the node must face the triangle across free space, not through the solid (the
        // far side of a thin wall lies behind its triangles).
        if ((node_at(X_, a) - rest.point).dot((B0 - A0).cross(C0 - A0)) <= 0) continue;
      }
      const ClosestPoint cp = closest_point_on_triangle(xa, node_at(x, t[0]), node_at(x, t[1]), node_at(x, t[2]));
      if (cp.distance >= best_distance) continue;
      best_distance = cp.distance;
      const Eigen::Vector3d offset = xa - cp.point;
      const double side = offset.dot(face_normal[f]) < 0 ? -1.0 : 1.0;  // behind the face: inside the solid
      best.triangle = f;
      best.weight = cp.weight;
      best.normal = cp.distance > 1e-12 * cell ? Eigen::Vector3d(side * offset / cp.distance) : face_normal[f];
      best.gap = side * cp.distance - settings_.gap;
    }
    if (best.triangle < 0) continue;
    best.relative_velocity = relative_velocity(best, u);
    candidates_.push_back(best);
  }
}

std::array<std::pair<int, double>, 4> SurfaceContact::entries(const Pair& p) const {
  const auto& t = triangles_[p.triangle].node;
  return {{{p.node, 1.0}, {t[0], -p.weight[0]}, {t[1], -p.weight[1]}, {t[2], -p.weight[2]}}};
}

double SurfaceContact::relative_velocity(const Pair& p, const Eigen::VectorXd& u) const {
  double g = 0;
  for (const auto& [v, c] : entries(p)) g += c * p.normal.dot(node_at(u, v));
  return g;
}

double SurfaceContact::friction_damping(const Pair& p, double force, const Eigen::VectorXd& u) const {
  if (!(settings_.friction > 0) || !(force > 0)) return 0.0;
  Eigen::Vector3d v_rel = Eigen::Vector3d::Zero();
  for (const auto& [v, c] : entries(p)) v_rel += c * node_at(u, v);
  const double slip = (v_rel - p.normal * p.normal.dot(v_rel)).norm();
  return settings_.friction * force / std::max(slip, settings_.friction_velocity);
}

void SurfaceContact::activate(Pair p) {
  p.kappa = settings_.penalty * mass_[p.node] / h_;  // from the node's inertia, as NewmarkIntegrator's
  p.target = -2.0 * std::max(p.gap, 0.0) / h_ - p.relative_velocity;
  active_.push_back(p);
}

bool SurfaceContact::warm_start() {
  if (touching_.empty()) return false;
  std::vector<char> touched(X_.size() / 3, 0);
  std::vector<double> force(X_.size() / 3, 0.0);
  for (std::size_t k = 0; k < touching_.size(); ++k)
    if (touching_[k] < static_cast<int>(touched.size())) {
      touched[touching_[k]] = 1;
      if (k < touching_force_.size()) force[touching_[k]] = touching_force_[k];
    }
  for (Pair p : candidates_)
    if (touched[p.node] && p.gap <= 1e-6 * h_) {  // still touching (1 µm/s over the step)
      p.force = force[p.node];
      p.friction = friction_damping(p, p.force, u_start_);
      activate(p);
    }
  return !active_.empty();
}

bool SurfaceContact::update(const Eigen::VectorXd& u_next) {
  bool changed = false;
  std::vector<char> is_active(X_.size() / 3, 0);
  for (size_t k = 0; k < active_.size();) {
    Pair& p = active_[k];
    p.force = p.kappa * (p.target - relative_velocity(p, u_next));
    // The friction for the next round's solve; a change of more than 1% is solved again.
    const double friction = friction_damping(p, p.force, u_next);
    changed = changed || std::abs(friction - p.friction) > 0.01 * std::max(friction, p.friction);
    p.friction = friction;
    if (p.force < 0) {
      active_[k] = active_.back();
      active_.pop_back();
      changed = true;
    } else {
      is_active[p.node] = 1;
      ++k;
    }
  }
  for (const Pair& p : candidates_) {
    if (is_active[p.node]) continue;
    if (!(p.gap + 0.5 * h_ * (p.relative_velocity + relative_velocity(p, u_next)) < 0)) continue;
    activate(p);
    changed = true;
  }
  return changed;
}

void SurfaceContact::add_rows(SparseMatrix& A, Eigen::VectorXd& b) const {
  if (active_.empty()) return;
  std::vector<Eigen::Triplet<double>> penalty;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(b.size());
  for (const Pair& p : active_) {
    const auto g = entries(p);
    for (const auto& [row_node, c_row] : g)
      for (int alpha = 0; alpha < 3; ++alpha) {
        const int row = 3 * row_node + alpha;
        if (prescribed_[row]) continue;
        rhs[row] += p.kappa * p.target * c_row * p.normal[alpha];
        for (const auto& [col_node, c_col] : g)
          for (int beta = 0; beta < 3; ++beta) {
            const int col = 3 * col_node + beta;
            const double nn = p.normal[alpha] * p.normal[beta];
            const double value = c_row * c_col * (p.kappa * nn + p.friction * ((alpha == beta) - nn));
            if (prescribed_[col])
              rhs[row] -= value * b[col] / A.coeff(col, col);  // the prescribed velocity, A_jj u_j = b_j
            else
              penalty.emplace_back(row, col, value);
          }
      }
  }
  SparseMatrix P(A.rows(), A.cols());
  P.setFromTriplets(penalty.begin(), penalty.end());
  A += P;
  b += rhs;
}

void SurfaceContact::finish(const Eigen::VectorXd& u_next) {
  touching_.clear();
  touching_force_.clear();
  solid_force_.assign(num_solids_, Eigen::Vector3d::Zero());
  for (Pair& p : active_) {
    p.force = p.kappa * (p.target - relative_velocity(p, u_next));
    touching_.push_back(p.node);
    touching_force_.push_back(p.force);
    const double f = std::max(0.0, p.force);
    solid_force_[node_solid_[p.node]] += f * p.normal;
    solid_force_[triangles_[p.triangle].solid] -= f * p.normal;
  }
}

Eigen::Vector3d SurfaceContact::contact_force(int solid) const {
  return solid < static_cast<int>(solid_force_.size()) ? solid_force_[solid] : Eigen::Vector3d::Zero();
}

}  // namespace tetfsi::solid
