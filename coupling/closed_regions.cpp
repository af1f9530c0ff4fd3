#include "coupling/closed_regions.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace tetfsi::coupling {
namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<ClosedRegion> find_closed_regions(const fluid::FluidMesh& fm, const std::vector<int>& unknown,
                                              const fluid::ClassifiedBoundary& bc,
                                              const std::vector<int>& solid_node) {
  // Connected sets of fluid tets (sharing a face), by union-find over the tet neighbours.
  const int T = fm.num_tets();
  std::vector<int> parent(T);
  std::iota(parent.begin(), parent.end(), 0);
  for (int t = 0; t < T; ++t)
    for (int k = 0; k < 4; ++k) {
      const int s = fm.neighbor[t][k];
      if (s < 0) continue;
      const int a = find_root(parent, t), b = find_root(parent, s);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<int> region_of_root(T, -1);
  std::vector<ClosedRegion> regions;
  std::vector<char> closed;
  for (int t = 0; t < T; ++t) {
    const int root = find_root(parent, t);
    if (region_of_root[root] < 0) {
      region_of_root[root] = static_cast<int>(regions.size());
      regions.emplace_back();
      closed.push_back(1);
    }
  }
  // Nodes of each region; a node with a prescribed pressure or flux opens its region.
  std::vector<int> node_region(fm.num_nodes(), -1);
  for (int t = 0; t < T; ++t) {
    const int r = region_of_root[find_root(parent, t)];
    for (int i : fm.tets[t]) {
      if (node_region[i] >= 0) continue;
      node_region[i] = r;
      regions[r].nodes.push_back(i);
      const bool flux = bc.flux.size() == fm.num_nodes() && bc.flux[i] != 0.0;
      if (unknown[i] < 0 || flux) closed[r] = 0;
    }
  }
  for (const fluid::BoundaryFace& f : fm.boundary_faces) {
    const int r = region_of_root[find_root(parent, f.tet)];
    std::array<int, 3> v;
    for (int k = 0; k < 3; ++k) v[k] = fm.node_to_mesh_vertex[f.nodes[k]];
    // Orient (a, b, c) so that (x_b − x_a) × (x_c − x_a) points out of the fluid, as f.normal.
    const Eigen::Vector3d& xa = fm.nodes[f.nodes[0]];
    if ((fm.nodes[f.nodes[1]] - xa).cross(fm.nodes[f.nodes[2]] - xa).dot(f.normal) < 0) std::swap(v[1], v[2]);
    regions[r].faces.push_back(v);
    for (int k = 0; k < 3; ++k) {
      const int s = solid_node[v[k]];
      if (s >= 0 && (regions[r].key < 0 || s < regions[r].key)) regions[r].key = s;
    }
  }
  std::vector<ClosedRegion> kept;
  for (std::size_t r = 0; r < regions.size(); ++r)
    if (closed[r] && regions[r].key >= 0) kept.push_back(std::move(regions[r]));
  return kept;
}

double region_volume(const ClosedRegion& region, const std::vector<Eigen::Vector3d>& x) {
  double six_v = 0;
  for (const auto& f : region.faces) six_v += x[f[0]].dot(x[f[1]].cross(x[f[2]]));
  return six_v / 6.0;
}

Eigen::VectorXd region_volume_gradient(const ClosedRegion& region, const std::vector<Eigen::Vector3d>& x,
                                       const std::vector<int>& solid_node, int num_solid_dofs) {
  Eigen::VectorXd a = Eigen::VectorXd::Zero(num_solid_dofs);
  for (const auto& f : region.faces) {
    // ∂V/∂x_a over the fan of a is Σ (A_f n_f)/3 (the terms x_a × ... cancel around a closed fan).
    const Eigen::Vector3d third_area_normal = (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]) / 6.0;
    for (int k = 0; k < 3; ++k)
      if (solid_node[f[k]] >= 0) a.segment<3>(3 * solid_node[f[k]]) += third_area_normal;
  }
  return a;
}

int ClosedVolumes::begin_step(const fluid::FluidMesh& fm, const std::vector<int>& unknown,
                              const fluid::ClassifiedBoundary& bc, const std::vector<int>& solid_node,
                              const std::vector<char>& fixed, const std::vector<Eigen::Vector3d>& x) {
  regions_.clear();
  volume_.clear();
  nonlinear_.clear();
  gradient_.clear();
  const int n = static_cast<int>(fixed.size());
  for (ClosedRegion& region : find_closed_regions(fm, unknown, bc, solid_node)) {
    Eigen::VectorXd a = region_volume_gradient(region, x, solid_node, n);
    bool free = false;
    for (int i = 0; i < n && !free; ++i) free = !fixed[i] && a[i] != 0.0;
    if (!free) continue;
    volume_.push_back(region_volume(region, x));
    nonlinear_.push_back(0.0);
    gradient_.push_back(std::move(a));
    reference_.emplace(region.key, volume_.back());  // kept if the key is known
    regions_.push_back(std::move(region));
  }
  return static_cast<int>(regions_.size());
}

void ClosedVolumes::project_start_velocity(Eigen::VectorXd& u, const Eigen::VectorXd& node_masses,
                                           const std::vector<char>& fixed, ClosedVolumeReport& report) const {
  const int k = static_cast<int>(regions_.size());
  if (k == 0) return;
  // M⁻¹ a_c on the free dofs.
  std::vector<Eigen::VectorXd> inv_mass_a(k);
  for (int c = 0; c < k; ++c) {
    inv_mass_a[c] = gradient_[c];
    for (Eigen::Index i = 0; i < u.size(); ++i)
      inv_mass_a[c][i] = fixed[i] || !(node_masses[i / 3] > 0) ? 0.0 : gradient_[c][i] / node_masses[i / 3];
  }
  Eigen::MatrixXd gram(k, k);
  Eigen::VectorXd flux(k);
  for (int c = 0; c < k; ++c) {
    flux[c] = gradient_[c].dot(u);
    for (int d = 0; d < k; ++d) gram(c, d) = gradient_[c].dot(inv_mass_a[d]);
  }
  // A region whose moving boundary is all prescribed has a zero row: leave it out.
  for (int c = 0; c < k; ++c)
    if (!(gram(c, c) > 0)) {
      gram.row(c).setZero();
      gram.col(c).setZero();
      gram(c, c) = 1;
      flux[c] = 0;
    }
  const Eigen::VectorXd lambda = gram.ldlt().solve(flux);
  Eigen::VectorXd du = Eigen::VectorXd::Zero(u.size());
  for (int c = 0; c < k; ++c) du += lambda[c] * inv_mass_a[c];
  // ½ (u − du)ᵀ M (u − du) = ½ uᵀ M u − ½ duᵀ M du, du being M-orthogonal to the projected u.
  double removed = 0;
  for (Eigen::Index i = 0; i < u.size(); ++i) removed += 0.5 * node_masses[i / 3] * du[i] * du[i];
  u -= du;
  report.removed_kinetic += removed;
}

Eigen::VectorXd ClosedVolumes::unit_source(int c, const fluid::FluidMesh& fm, const std::vector<int>& unknown,
                                           int m) const {
  Eigen::VectorXd w = Eigen::VectorXd::Zero(m);
  double dual = 0;
  for (int i : regions_[c].nodes) dual += fm.dual_volume[i];
  if (dual > 0)
    for (int i : regions_[c].nodes) w[unknown[i]] = fm.dual_volume[i] / dual;
  return w;
}

std::vector<double> ClosedVolumes::excess(const std::vector<Eigen::Vector3d>& x) const {
  std::vector<double> e;
  for (const ClosedRegion& region : regions_) e.push_back(region_volume(region, x) - reference_.at(region.key));
  return e;
}

void ClosedVolumes::predict_motion(const std::vector<Eigen::Vector3d>& x_predicted) {
  // The projected ū has aᵀū = 0, so q̂ = V(xⁿ + h ū) − V(xⁿ).
  for (std::size_t c = 0; c < regions_.size(); ++c) nonlinear_[c] = region_volume(regions_[c], x_predicted) - volume_[c];
}

void ClosedVolumes::add_volume_source(double h, const fluid::FluidMesh& fm, const std::vector<int>& unknown,
                                      Eigen::VectorXd& r, ClosedVolumeReport& report) const {
  report.regions = static_cast<int>(regions_.size());
  double largest = -1;
  for (std::size_t c = 0; c < regions_.size(); ++c) {
    const double v0 = reference_.at(regions_[c].key);
    const double source = 2.0 * (v0 - volume_[c] - nonlinear_[c]) / h;  // S_c [m³/s]
    r += source * unit_source(static_cast<int>(c), fm, unknown, static_cast<int>(r.size()));
    const double error = (volume_[c] - v0) / v0;
    if (std::abs(error) > largest) {
      largest = std::abs(error);
      report.error = error;
      report.correction = h * source / v0;
    }
  }
}

double ClosedVolumes::relative_error(const std::vector<Eigen::Vector3d>& x) const {
  double worst = 0;
  for (const ClosedRegion& region : regions_) {
    const double v0 = reference_.at(region.key);
    const double error = (region_volume(region, x) - v0) / v0;
    if (std::abs(error) > std::abs(worst)) worst = error;
  }
  return worst;
}

}  // namespace tetfsi::coupling
