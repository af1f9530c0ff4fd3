/// @file nodal_advection.cpp
/// Semi-Lagrangian advection of nodal (P1) fields, such as a liquid's level set, across meshes
/// (advect_nodal, advect_nodal_bfecc in semi_lagrangian.hpp).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <optional>
#include <stdexcept>

#include "fluid/advection/semi_lagrangian.hpp"

namespace tetfsi::fluid {
namespace {

constexpr int kBlock = 256;  ///< samples per deterministic work block

/// Nodal velocity (weighted node averages of the tet velocities) with the field in slot 3.
using NodalState = std::vector<Eigen::Vector4d>;

NodalState nodal_state(const FluidMesh& mesh, const TetVectors& velocity, const Eigen::VectorXd& values,
                       const std::vector<double>* node_weight) {
  std::vector<Eigen::Vector4d> per_tet(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) per_tet[t] << velocity[t], 0.0;
  NodalState nodal = weighted_node_average(mesh, per_tet, node_weight);
  for (int i = 0; i < mesh.num_nodes(); ++i) nodal[i][3] = values[i];
  return nodal;
}

Eigen::Vector4d interp(const FluidMesh& m, const NodalState& nodal, const Location& l) {
  Eigen::Vector4d v = Eigen::Vector4d::Zero();
  for (int k = 0; k < 4; ++k) v += l.bary[k] * nodal[m.tets[l.tet][k]];
  return v;
}

double interp_value(const FluidMesh& m, const Eigen::VectorXd& values, const Location& l) {
  double v = 0.0;
  for (int k = 0; k < 4; ++k) v += l.bary[k] * values[m.tets[l.tet][k]];
  return v;
}

/// Where each node of `new_mesh` came from over h: an RK2 trace back through the old nodal
/// velocity, each point clamped to the old fluid (see advect_nodal).
std::vector<Location> feet_of(const FluidMesh& old_mesh, const NodalState& nodal, const FluidMesh& new_mesh,
                              double h, const PointLocator& locator, AdvectionReport* report) {
  const int n = new_mesh.num_nodes();
  // A moved mesh keeps its nodes: node i's walk starts at one of its old tets.
  const bool same_nodes = !matching_tets(old_mesh, new_mesh).empty();
  std::vector<Location> feet(n);
  std::atomic<int> clamped_total{0}, outside_total{0};
  const int blocks = (n + kBlock - 1) / kBlock;
  tbb::parallel_for(0, blocks, [&](int b) {
    int hint = -1, clamped = 0, outside = 0;
    for (int i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
      if (same_nodes) hint = old_mesh.node_tets[old_mesh.mesh_vertex_to_node[new_mesh.node_to_mesh_vertex[i]]].front();
      // Points that leave the fluid are clamped to it (the locator's clamped barycentric
      // coordinates in the boundary tet its walk ended in), not cut back along the trace: a node
      // on a wall whose velocity has the slightest outward part would otherwise hardly move.
      const Eigen::Vector3d& x0 = new_mesh.nodes[i];
      const Location l0 = locator.locate(x0, hint);
      outside += !l0.inside;
      const Location lm = locator.locate(x0 - 0.5 * h * interp(old_mesh, nodal, l0).head<3>(), l0.tet);
      feet[i] = locator.locate(x0 - h * interp(old_mesh, nodal, lm).head<3>(), lm.tet);
      clamped += !lm.inside || !feet[i].inside;
      hint = l0.tet;
    }
    clamped_total += clamped;
    outside_total += outside;
  });
  if (report) {
    report->clamped = clamped_total;
    report->outside_start = outside_total;
  }
  return feet;
}

void check_sizes(const FluidMesh& old_mesh, const TetVectors& old_velocity, const Eigen::VectorXd& old_values,
                 const std::vector<double>* node_weight, const char* who) {
  if (static_cast<int>(old_velocity.size()) != old_mesh.num_tets() || old_values.size() != old_mesh.num_nodes() ||
      (node_weight && static_cast<int>(node_weight->size()) != old_mesh.num_tets()))
    throw std::invalid_argument(std::string(who) + ": old velocity, values or weights do not match the old mesh");
}

/// Steps shared by advect_nodal and advect_nodal_bfecc: the old nodal state, the feet of the new
/// nodes and the first-order values read there.
struct FirstOrder {
  NodalState nodal;
  std::vector<Location> feet;
  Eigen::VectorXd values;
};

FirstOrder first_order(const FluidMesh& old_mesh, const TetVectors& old_velocity, const Eigen::VectorXd& old_values,
                       const FluidMesh& new_mesh, double h, AdvectionReport* report,
                       const std::vector<double>* node_weight, const PointLocator& locator) {
  FirstOrder f;
  f.nodal = nodal_state(old_mesh, old_velocity, old_values, node_weight);
  f.feet = feet_of(old_mesh, f.nodal, new_mesh, h, locator, report);
  f.values.resize(new_mesh.num_nodes());
  tbb::parallel_for(0, new_mesh.num_nodes(), [&](int i) { f.values[i] = interp_value(old_mesh, old_values, f.feet[i]); });
  return f;
}

}  // namespace

Eigen::VectorXd advect_nodal(const FluidMesh& old_mesh, const TetVectors& old_velocity,
                             const Eigen::VectorXd& old_values, const FluidMesh& new_mesh, double h,
                             AdvectionReport* report, const std::vector<double>* node_weight,
                             const PointLocator* given_locator) {
  check_sizes(old_mesh, old_velocity, old_values, node_weight, "advect_nodal");
  std::optional<PointLocator> own_locator;
  if (!given_locator) own_locator.emplace(old_mesh);
  return first_order(old_mesh, old_velocity, old_values, new_mesh, h, report, node_weight,
                     given_locator ? *given_locator : *own_locator)
      .values;
}

Eigen::VectorXd advect_nodal_bfecc(const FluidMesh& old_mesh, const TetVectors& old_velocity,
                                   const Eigen::VectorXd& old_values, const FluidMesh& new_mesh, double h,
                                   AdvectionReport* report, const std::vector<double>* node_weight,
                                   const PointLocator* given_locator) {
  check_sizes(old_mesh, old_velocity, old_values, node_weight, "advect_nodal_bfecc");
  std::optional<PointLocator> own_locator;
  if (!given_locator) own_locator.emplace(old_mesh);
  const PointLocator& old_locator = given_locator ? *given_locator : *own_locator;
  // 1. Forward: phi_hat = A(phi) on the new nodes.
  const FirstOrder a = first_order(old_mesh, old_velocity, old_values, new_mesh, h, report, node_weight, old_locator);
  const NodalState& nodal = a.nodal;
  const std::vector<Location>& feet = a.feet;
  const Eigen::VectorXd& phi_hat = a.values;
  // 2. Backward: phi_check = A^R(phi_hat) on the old nodes, traced forward (RK2) through the same
  //    velocity and read on the new mesh.
  const PointLocator new_locator(new_mesh);
  const int n_old = old_mesh.num_nodes();
  Eigen::VectorXd correction(n_old);
  const int blocks = (n_old + kBlock - 1) / kBlock;
  tbb::parallel_for(0, blocks, [&](int b) {
    int hint = -1;
    for (int i = b * kBlock; i < std::min(n_old, (b + 1) * kBlock); ++i) {
      const Eigen::Vector3d& x0 = old_mesh.nodes[i];
      const Location lm = old_locator.locate(x0 + 0.5 * h * nodal[i].head<3>(), old_mesh.node_tets[i].front());
      const Location head = new_locator.locate(x0 + h * interp(old_mesh, nodal, lm).head<3>(), hint);
      hint = head.tet;
      // 3. Half the round trip's error: phi + (phi - phi_check) / 2 (Dupont & Liu 2003).
      correction[i] = 0.5 * (old_values[i] - interp_value(new_mesh, phi_hat, head));
    }
  });
  // 4. A(phi + correction) = phi_hat + A(correction), limited to the values at the foot's nodes:
  //    where it leaves them, the first-order value is kept (Selle et al. 2008).
  Eigen::VectorXd out(new_mesh.num_nodes());
  tbb::parallel_for(0, new_mesh.num_nodes(), [&](int i) {
    const auto& tet = old_mesh.tets[feet[i].tet];
    double lo = old_values[tet[0]], hi = lo;
    for (int k = 1; k < 4; ++k) {
      lo = std::min(lo, old_values[tet[k]]);
      hi = std::max(hi, old_values[tet[k]]);
    }
    const double v = phi_hat[i] + interp_value(old_mesh, correction, feet[i]);
    out[i] = v < lo || v > hi ? phi_hat[i] : v;
  });
  return out;
}

}  // namespace tetfsi::fluid
