#include "fluid/liquid/free_surface_projection.hpp"

#include <tbb/parallel_for.h>

#include <chrono>
#include <numeric>
#include <stdexcept>
#include <string>

#include "fluid/liquid/cut_tet.hpp"

namespace tetfsi::fluid {
namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// Bodies of liquid that touch neither the surface nor an open face have a pressure defined up to a
/// constant: for each such body, remove the mean of its right-hand side and pin its lowest node
/// (unknown[i] = -1). Returns the number of pinned bodies.
int pin_isolated_bodies(const FluidMesh& mesh, const LiquidGeometry& liquid, std::vector<int>& unknown,
                        Eigen::VectorXd& rhs) {
  const int n = mesh.num_nodes();
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> grounded(n, 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (liquid.liquid_volume[t] <= 0.0) continue;
    int first = -1;
    bool touches_dirichlet = false;
    for (int k = 0; k < 4; ++k) {
      const int i = mesh.tets[t][k];
      if (unknown[i] < 0) {
        touches_dirichlet = true;
        continue;
      }
      if (first < 0) first = i;
      else parent[find_root(parent, i)] = find_root(parent, first);
    }
    if (first >= 0 && touches_dirichlet) grounded[find_root(parent, first)] = 1;
  }
  std::vector<double> sum(n, 0.0);
  std::vector<int> count(n, 0), lowest(n, -1);
  for (int i = 0; i < n; ++i) {
    if (unknown[i] < 0) continue;
    const int r = find_root(parent, i);
    grounded[r] = grounded[r] || grounded[i];
  }
  for (int i = 0; i < n; ++i) {
    if (unknown[i] < 0) continue;
    const int r = find_root(parent, i);
    if (grounded[r]) continue;
    sum[r] += rhs[i];
    ++count[r];
    if (lowest[r] < 0) lowest[r] = i;
  }
  int pinned = 0;
  for (int i = 0; i < n; ++i) {
    if (unknown[i] < 0) continue;
    const int r = find_root(parent, i);
    if (!grounded[r]) rhs[i] -= sum[r] / count[r];
  }
  for (int r = 0; r < n; ++r)
    if (lowest[r] >= 0) {
      unknown[lowest[r]] = -1;
      ++pinned;
    }
  return pinned;
}

}  // namespace

double LiquidGeometry::total_volume() const {
  double v = 0.0;
  for (double x : liquid_volume) v += x;
  return v;
}

LiquidGeometry liquid_geometry(const FluidMesh& mesh, const Eigen::VectorXd& phi) {
  if (phi.size() != mesh.num_nodes())
    throw std::invalid_argument("liquid_geometry: the level set has " + std::to_string(phi.size()) +
                                " values for " + std::to_string(mesh.num_nodes()) + " nodes");
  LiquidGeometry g;
  const int nt = mesh.num_tets();
  g.liquid_volume.assign(nt, 0.0);
  g.wet_moment.resize(nt);
  g.first_moment.assign(nt, Eigen::Vector3d::Zero());
  g.is_liquid.resize(mesh.num_nodes());
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    g.is_liquid[i] = phi[i] < 0.0;
    g.num_air_nodes += !g.is_liquid[i];
  }
  tbb::parallel_for(0, nt, [&](int t) {
    const auto& tet = mesh.tets[t];
    int liquid = 0;
    for (int k = 0; k < 4; ++k) liquid += g.is_liquid[tet[k]];
    if (liquid == 4) {  // the ordinary P1 terms: |Omega_t| = V_t, a_k = V_t grad(phi_k)
      g.liquid_volume[t] = mesh.volume[t];
      for (int k = 0; k < 4; ++k) g.wet_moment[t][k] = mesh.volume[t] * mesh.grad[t][k];
      g.first_moment[t] = mesh.volume[t] * mesh.centroid(t);
      return;
    }
    for (auto& a : g.wet_moment[t]) a.setZero();
    if (liquid == 0) return;
    const CutTet c = cut_tet({mesh.nodes[tet[0]], mesh.nodes[tet[1]], mesh.nodes[tet[2]], mesh.nodes[tet[3]]},
                             {phi[tet[0]], phi[tet[1]], phi[tet[2]], phi[tet[3]]});
    g.liquid_volume[t] = c.liquid_volume;
    g.wet_moment[t] = c.wet_moment;
    g.first_moment[t] = c.first_moment;
  });
  return g;
}

Eigen::VectorXd wet_gradient_transpose(const FluidMesh& mesh, const LiquidGeometry& liquid, const TetVectors& u) {
  // Gathered per node over its tets (ascending): deterministic in parallel.
  Eigen::VectorXd r(mesh.num_nodes());
  tbb::parallel_for(0, mesh.num_nodes(), [&](int i) {
    double s = 0.0;
    for (int t : mesh.node_tets[i]) {
      int k = 0;
      while (mesh.tets[t][k] != i) ++k;
      s += liquid.wet_moment[t][k].dot(u[t]);
    }
    r[i] = s;
  });
  return r;
}

Eigen::SparseMatrix<double> wet_laplacian(const FluidMesh& mesh, const LiquidGeometry& liquid,
                                          const std::vector<int>& unknown, int m) {
  const int nt = mesh.num_tets();
  std::vector<Eigen::Triplet<double>> trip(16 * static_cast<size_t>(nt), Eigen::Triplet<double>(0, 0, 0.0));
  tbb::parallel_for(0, nt, [&](int t) {
    const double v = liquid.liquid_volume[t];
    if (v <= 0.0) return;
    for (int a = 0; a < 4; ++a) {
      const int ra = unknown[mesh.tets[t][a]];
      if (ra < 0) continue;
      for (int b = 0; b < 4; ++b) {
        const int cb = unknown[mesh.tets[t][b]];
        if (cb >= 0)
          trip[16 * static_cast<size_t>(t) + 4 * a + b] =
              Eigen::Triplet<double>(ra, cb, liquid.wet_moment[t][a].dot(liquid.wet_moment[t][b]) / v);
      }
    }
  });
  Eigen::SparseMatrix<double> a(m, m);
  a.setFromTriplets(trip.begin(), trip.end());  // unused slots add 0 to (0, 0)
  return a;
}

void apply_wet_pressure(const FluidMesh& mesh, const LiquidGeometry& liquid, const Eigen::VectorXd& pressure,
                        double h, double density, TetVectors& u) {
  const double scale = h / density;
  tbb::parallel_for(0, mesh.num_tets(), [&](int t) {
    const double v = liquid.liquid_volume[t];
    if (v <= 0.0) return;
    Eigen::Vector3d grad_p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) grad_p += pressure[mesh.tets[t][k]] * liquid.wet_moment[t][k];
    u[t] -= (scale / v) * grad_p;
  });
}

double liquid_kinetic_energy(const LiquidGeometry& liquid, const TetVectors& u) {
  double e = 0.0;
  for (size_t t = 0; t < u.size(); ++t) e += 0.5 * liquid.liquid_volume[t] * u[t].squaredNorm();
  return e;
}

ProjectionReport project_free_surface(const FluidMesh& mesh, const ClassifiedBoundary& bc,
                                      const LiquidGeometry& liquid, double h, double density, TetVectors& u,
                                      const SolverOptions& options) {
  if (!(h > 0.0) || !(density > 0.0))
    throw std::invalid_argument("project_free_surface: time step and density must be positive");
  const int n = mesh.num_nodes(), nt = mesh.num_tets();
  if (static_cast<int>(u.size()) != nt || static_cast<int>(liquid.liquid_volume.size()) != nt ||
      static_cast<int>(liquid.is_liquid.size()) != n)
    throw std::invalid_argument("project_free_surface: velocity or liquid geometry does not match the mesh");
  ProjectionReport rep;
  const double t0 = now();
  // rhs_i = (rho/h) (sum_t a_i . u*_t - f_i).
  const Eigen::VectorXd rhs = (density / h) * (wet_gradient_transpose(mesh, liquid, u) - bc.flux);
  std::vector<int> unknown(n, -1);
  for (int i = 0; i < n; ++i)
    if (liquid.is_liquid[i] && bc.node_kind[i] != NodeKind::kOpen) unknown[i] = 0;
  Eigen::VectorXd pinned_rhs = rhs;
  pin_isolated_bodies(mesh, liquid, unknown, pinned_rhs);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (unknown[i] >= 0) unknown[i] = m++;
  if (m == 0) throw std::invalid_argument("project_free_surface: no liquid node to solve for");
  const Eigen::SparseMatrix<double> a = wet_laplacian(mesh, liquid, unknown, m);
  rep.assemble_seconds = now() - t0;
  solve_on_unknowns(a, pinned_rhs, unknown, m, options, rep);
  apply_wet_pressure(mesh, liquid, rep.pressure, h, density, u);
  // Weak divergence at the unknowns per unit dual volume (the measure of projection.hpp).
  const Eigen::VectorXd div = bc.flux - wet_gradient_transpose(mesh, liquid, u);
  for (int i = 0; i < n; ++i)
    if (unknown[i] >= 0) rep.max_divergence = std::max(rep.max_divergence, std::abs(div[i]) / mesh.dual_volume[i]);
  return rep;
}

}  // namespace tetfsi::fluid
