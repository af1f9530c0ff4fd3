#include "fluid/viscosity/node_fit.hpp"

#include <Eigen/Cholesky>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace tetfsi::fluid {
namespace {

using Monomials = Eigen::Matrix<double, 10, 1>;

/// Smallest eigenvalue of the normal matrix divided by its (0,0) entry (the total weight) for a fit
/// to count as determined, with d scaled by the largest distance over the tets around the node's
/// neighbours. Looser thresholds let near-degenerate quadratic fits of boundary nodes extrapolate
/// wildly (1e-5: the random-field energy test gains energy; 1e-4: none, test_viscosity.cpp).
const double kMinEigenvalue = 1e-4;

/// 1, d, and the six products d_a d_b / 2 (a <= b; the squares halved) of d = (x - x_i) / scale.
Monomials monomials(const Eigen::Vector3d& d) {
  Monomials m;
  m << 1.0, d.x(), d.y(), d.z(), 0.5 * d.x() * d.x(), 0.5 * d.y() * d.y(), 0.5 * d.z() * d.z(), d.x() * d.y(),
      d.x() * d.z(), d.y() * d.z();
  return m;
}

/// Least-squares fit of the first `Terms` monomials over `tets`; false if they do not determine it
/// (kMinEigenvalue).
template <int Terms>
bool fit(const FluidMesh& mesh, int i, const std::vector<int>& tets, const std::vector<double>& weight,
         const TetVectors& u, double scale, Eigen::Matrix<double, 3, 10>& out) {
  // The weighted design matrix D (rows sqrt(w_t) monomials(d_t)) and data R (rows sqrt(w_t) u_t):
  // normal = D^T D, rhs = D^T R, as matrix products (rings hold up to a few hundred tets).
  constexpr int kMaxRows = 512;
  Eigen::Matrix<double, Eigen::Dynamic, Terms, Eigen::ColMajor, kMaxRows, Terms> D;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, kMaxRows, 3> R;
  const int rows = static_cast<int>(std::min<std::size_t>(tets.size(), kMaxRows));
  D.resize(rows, Terms);
  R.resize(rows, 3);
  int used = 0;
  for (int t : tets) {
    if (!(weight[t] > 0) || used == kMaxRows) continue;
    const double root = std::sqrt(weight[t]);
    D.row(used) = root * monomials((mesh.centroid(t) - mesh.nodes[i]) / scale).head<Terms>().transpose();
    R.row(used) = root * u[t].transpose();
    ++used;
  }
  if (used < Terms) return false;
  // The lower triangle by a symmetric rank update (half the products of D^T D).
  Eigen::Matrix<double, Terms, Terms> normal = Eigen::Matrix<double, Terms, Terms>::Zero();
  normal.template selfadjointView<Eigen::Lower>().rankUpdate(D.topRows(used).transpose());
  normal.template triangularView<Eigen::StrictlyUpper>() = normal.transpose();
  if (!(normal(0, 0) > 0)) return false;
  // Smallest eigenvalue of normal / normal(0,0) above kMinEigenvalue <=> this shifted matrix is
  // positive definite, which its Cholesky factorization tells (cheaper than the eigenvalues).
  const Eigen::Matrix<double, Terms, Terms> shifted =
      normal / normal(0, 0) - kMinEigenvalue * Eigen::Matrix<double, Terms, Terms>::Identity();
  if (Eigen::LLT<Eigen::Matrix<double, Terms, Terms>>(shifted).info() != Eigen::Success) return false;
  const Eigen::Matrix<double, Terms, 3> rhs = D.topRows(used).transpose().lazyProduct(R.topRows(used));
  out.setZero();
  out.template leftCols<Terms>() = Eigen::LLT<Eigen::Matrix<double, Terms, Terms>>(normal).solve(rhs).transpose();
  return true;
}

}  // namespace

Eigen::Vector3d NodeFits::at(const FluidMesh& mesh, int i, const Eigen::Vector3d& x) const {
  return coefficient[i] * monomials((x - mesh.nodes[i]) / scale[i]);
}

NodeRings node_rings(const FluidMesh& mesh) {
  NodeRings rings(mesh.num_nodes());
  // Per thread, the last node whose ring listed each tet and each node.
  struct Listed {
    std::vector<int> tet, node;
  };
  tbb::enumerable_thread_specific<Listed> listed_for(
      Listed{std::vector<int>(mesh.num_tets(), -1), std::vector<int>(mesh.num_nodes(), -1)});
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    Listed& listed = listed_for.local();
    std::vector<int> around;  // i and its neighbours
    for (int t : mesh.node_tets[i])
      for (int j : mesh.tets[t])
        if (listed.node[j] != i) {
          listed.node[j] = i;
          around.push_back(j);
        }
    std::vector<int>& ring = rings[i];
    ring.reserve(8 * mesh.node_tets[i].size());
    for (int j : around)
      for (int s : mesh.node_tets[j])
        if (listed.tet[s] != i) {
          listed.tet[s] = i;
          ring.push_back(s);
        }
  });
  return rings;
}

NodeFits fit_at_nodes(const FluidMesh& mesh, const std::vector<double>& weight, const TetVectors& u,
                      const NodeRings& rings) {
  NodeFits fits;
  fits.coefficient.assign(mesh.num_nodes(), Eigen::Matrix<double, 3, 10>::Zero());
  fits.scale.assign(mesh.num_nodes(), 1.0);
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    const std::vector<int>& ring = rings[i];
    // The scale of d: the largest centroid distance over the ring (every monomial at most 1).
    double scale = 0;
    for (int t : ring) scale = std::max(scale, (mesh.centroid(t) - mesh.nodes[i]).norm());
    if (!(scale > 0)) return;
    fits.scale[i] = scale;
    Eigen::Matrix<double, 3, 10>& c = fits.coefficient[i];
    // The tets around i alone almost never determine a quadratic (their centroids lie at about one
    // distance from x_i, so |d|^2 is nearly the constant monomial): the quadratic is fitted over the
    // ring, the linear fall-backs over the tets around i first.
    if (fit<10>(mesh, i, ring, weight, u, scale, c) || fit<4>(mesh, i, mesh.node_tets[i], weight, u, scale, c) ||
        fit<4>(mesh, i, ring, weight, u, scale, c))
      return;
    // The weighted average over the tets around i (no fluid around i: 0).
    double total = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int t : mesh.node_tets[i]) {
      total += weight[t];
      sum += weight[t] * u[t];
    }
    c.setZero();
    if (total > 0) c.col(0) = sum / total;
  });
  return fits;
}

}  // namespace tetfsi::fluid
