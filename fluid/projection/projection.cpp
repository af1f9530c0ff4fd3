#include "fluid/projection/projection.hpp"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "support/number_text.hpp"

namespace tetfsi::fluid {
namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

Eigen::VectorXd weak_divergence(const FluidMesh& mesh, const ClassifiedBoundary& bc, const TetVectors& u) {
  return bc.flux - gradient_transpose_volume(mesh, u);
}

double max_normalized_divergence(const FluidMesh& mesh, const ClassifiedBoundary& bc, const TetVectors& u) {
  const Eigen::VectorXd d = weak_divergence(mesh, bc, u);
  double m = 0.0;
  for (int i = 0; i < mesh.num_nodes(); ++i)
    if (bc.node_kind[i] != NodeKind::kOpen) m = std::max(m, std::abs(d[i]) / mesh.dual_volume[i]);
  return m;
}

void solve_on_unknowns(const Eigen::SparseMatrix<double>& a, const Eigen::VectorXd& rhs, const std::vector<int>& unknown,
                       int m, const SolverOptions& options, ProjectionReport& rep) {
  const int n = static_cast<int>(unknown.size());
  Eigen::VectorXd b(m);
  for (int i = 0; i < n; ++i)
    if (unknown[i] >= 0) b[unknown[i]] = rhs[i];
  rep.unknowns = m;
  const double t0 = now();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(m);
  rep.solve = solve_spd(a, b, x, options);
  rep.solve_seconds = now() - t0;
  rep.pressure = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    if (unknown[i] >= 0) rep.pressure[i] = x[unknown[i]];
}

ProjectionReport project(const FluidMesh& mesh, const ClassifiedBoundary& bc, double h, double density,
                         TetVectors& u, const SolverOptions& options) {
  if (!(h > 0.0) || !(density > 0.0))
    throw std::invalid_argument("project: time step and density must be positive");
  if (static_cast<int>(u.size()) != mesh.num_tets())
    throw std::invalid_argument("project: velocity has " + std::to_string(u.size()) + " entries for " +
                                std::to_string(mesh.num_tets()) + " tets");
  ProjectionReport rep;
  const double t0 = now();
  const int n = mesh.num_nodes();
  // rhs_i = (rho/h) (G^T V u* - f)_i, so that L p = rhs.
  Eigen::VectorXd rhs = (density / h) * (gradient_transpose_volume(mesh, u) - bc.flux);
  std::vector<int> unknown(n, -1);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (bc.node_kind[i] != NodeKind::kOpen) unknown[i] = m++;
  if (bc.closed) {
    const double net = bc.flux.sum();
    const double scale = bc.flux.cwiseAbs().sum();
    if (std::abs(net) > 1e-8 * scale)
      throw std::invalid_argument("project: closed fluid domain (no open boundary) with net inflow " +
                                  number_text(net) + " m^3/s: incompressible flow has no solution");
    rhs.array() -= rhs.mean();
    unknown[0] = -1;  // pin node 0
    m = 0;
    for (int i = 0; i < n; ++i)
      if (unknown[i] >= 0) unknown[i] = m++;
  }
  if (m == 0) throw std::invalid_argument("project: every fluid node is on an open boundary: nothing to solve");
  // Reduced L (rows/columns of unknown nodes only; the unknowns are numbered in node order).
  const Eigen::SparseMatrix<double> a = assemble_laplacian(mesh, unknown, m);
  rep.assemble_seconds = now() - t0;
  solve_on_unknowns(a, rhs, unknown, m, options, rep);
  if (bc.closed) {
    double pv = 0.0, vol = 0.0;
    for (int i = 0; i < n; ++i) {
      pv += mesh.dual_volume[i] * rep.pressure[i];
      vol += mesh.dual_volume[i];
    }
    rep.pressure.array() -= pv / vol;
  }
  const TetVectors gp = gradient(mesh, rep.pressure);
  for (int t = 0; t < mesh.num_tets(); ++t) u[t] -= (h / density) * gp[t];
  rep.max_divergence = max_normalized_divergence(mesh, bc, u);
  return rep;
}

}  // namespace tetfsi::fluid
