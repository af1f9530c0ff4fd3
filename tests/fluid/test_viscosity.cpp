// Implicit viscosity (fluid/viscosity/implicit_viscosity.hpp) on unstructured meshes: a structured
// box whose interior is jittered and then remeshed by CGAL (mesh::remesh_step), so that no node
// sits on a lattice. Exact solutions of the viscous step: Couette (linear) flow is the steady
// state to solver precision; plane Poiseuille (quadratic) flow converges at second order (P1
// reproduces linear fields, not quadratic ones); a shear wave between no-slip plates decays at
// nu k^2; rigid rotation carries no viscous stress (stress form); no step adds energy.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fluid/viscosity/implicit_viscosity.hpp"
#include "fluid_test_support.hpp"
#include "mesh/remesher.hpp"

namespace tetfsi::fluid {
namespace {

const Eigen::Vector3d kLo(0, 0, 0), kHi(0.6, 0.3, 0.6);

/// The box [kLo, kHi] meshed at edge `h`, interior jittered and remeshed once by CGAL.
FluidMesh unstructured_box(double h) {
  const Eigen::Vector3i n = ((kHi - kLo) / h).array().round().cast<int>();
  mesh::TetMesh m = mesh::structured_box(kLo, kHi, n.x(), n.y(), n.z());
  std::mt19937 rng(11);
  m = testing::jittered(m, kLo, kHi, h, 0.08, rng);
  mesh::RemeshOptions options;
  options.target_edge_length = h;
  options.iterations = 1;
  const mesh::RemeshResult r = mesh::remesh_step(m, m.vertices, options);
  EXPECT_TRUE(r.report.remeshed);
  return build_fluid_mesh(r.mesh);
}

bool on_box_boundary(const Eigen::Vector3d& x) {
  return ((x - kLo).array().abs() < 1e-9).any() || ((x - kHi).array().abs() < 1e-9).any();
}

/// Every node on the box's faces held at `exact`.
ViscousNodes box_held_at(const FluidMesh& m, const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& exact) {
  ViscousNodes nodes;
  nodes.fixed.assign(m.num_nodes(), 0);
  nodes.velocity.assign(m.num_nodes(), Eigen::Vector3d::Zero());
  for (int i = 0; i < m.num_nodes(); ++i)
    if (on_box_boundary(m.nodes[i])) {
      nodes.fixed[i] = 1;
      nodes.velocity[i] = exact(m.nodes[i]);
    }
  return nodes;
}

/// Largest |u_t - exact(c_t)| over the tets (c_t the centroid: a linear field's tet mean).
double tet_error(const FluidMesh& m, const TetVectors& u,
                 const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& exact) {
  double e = 0;
  for (int t = 0; t < m.num_tets(); ++t) e = std::max(e, (u[t] - exact(m.centroid(t))).norm());
  return e;
}

SolverOptions tight() { return {SolverBackend::kEigenIcCg, 1e-12, 5000}; }

double energy(const FluidMesh& m, const TetVectors& u) { return kinetic_energy(m, u); }

TEST(Viscosity, CouetteFlowIsTheSteadyStateToSolverPrecision) {
  const FluidMesh m = unstructured_box(0.1);
  const double U = 2.0, H = kHi.z(), mu = 1.0, rho = 1.0, h = 1.0;  // h mu / (rho dx^2) = 100
  auto exact = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(U * x.z() / H, 0, 0); };
  const ViscousNodes nodes = box_held_at(m, exact);
  TetVectors u(m.num_tets(), Eigen::Vector3d::Zero());
  const std::vector<double> viscosity(m.num_tets(), mu);
  double e = 0;
  int steps = 0;
  for (; steps < 400; ++steps) {
    apply_viscosity(m, viscosity, m.volume, rho, nodes, h, tight(), u);
    e = tet_error(m, u, exact);
    if (e <= 1e-9 * U) break;
  }
  std::printf("Couette on %d tets: max |u_t - u_exact(c_t)| / U = %.3g after %d steps\n", m.num_tets(), e / U,
              steps + 1);
  EXPECT_LE(e, 1e-8 * U);
}

TEST(Viscosity, PlanePoiseuilleFlowConvergesAtSecondOrder) {
  // u_x = f z (H - z) / (2 nu) between plates z = 0 and z = H driven by the body force f along x.
  const double f = 3.0, mu = 0.5, rho = 1.0, H = kHi.z(), h = 1.0;
  auto exact = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(f * rho * x.z() * (H - x.z()) / (2 * mu), 0, 0); };
  const double peak = exact({0, 0, H / 2}).x();
  std::vector<double> errors, edges = {0.1, 0.05};
  for (double edge : edges) {
    const FluidMesh m = unstructured_box(edge);
    const ViscousNodes nodes = box_held_at(m, exact);
    TetVectors u(m.num_tets(), Eigen::Vector3d::Zero());
    const std::vector<double> viscosity(m.num_tets(), mu);
    double e = 0, previous = 1e300;
    for (int step = 0; step < 600 && std::abs(previous - e) > 1e-12 * peak; ++step) {
      for (auto& v : u) v.x() += h * f;
      apply_viscosity(m, viscosity, m.volume, rho, nodes, h, tight(), u);
      previous = e;
      e = tet_error(m, u, exact);
    }
    std::printf("Poiseuille edge %.3f m, %d tets: max tet error / peak = %.3g\n", edge, m.num_tets(), e / peak);
    errors.push_back(e / peak);
  }
  const double order = std::log(errors[0] / errors[1]) / std::log(edges[0] / edges[1]);
  std::printf("observed order %.2f\n", order);
  EXPECT_GE(order, 1.7);
  EXPECT_LE(errors[1], 0.02);
}

TEST(Viscosity, ShearWaveBetweenNoSlipPlatesDecaysAtNuKSquared) {
  // u_x = A sin(k z) e^{-nu k^2 t}, k = pi / H: plates at rest at z = 0, H; the other faces held at
  // the exact value of each step's end. The decay over tau = 1 / (nu k^2), fitted to the tets: within
  // 2% of the exact 1 at 6 cells per half wave, 1% at 12 (100 steps: backward Euler alone would
  // give n ln(1 + 1/n) = 0.995).
  const double H = kHi.z(), k = M_PI / H, mu = 0.01, rho = 1.0, nu = mu / rho, tau = 1 / (nu * k * k);
  const int steps = 100;
  const double h = tau / steps, backward_euler = steps * std::log1p(1.0 / steps);
  std::vector<double> errors, edges = {0.1, 0.05};
  for (double edge : edges) {
    const FluidMesh m = unstructured_box(edge);
    TetVectors u(m.num_tets());
    for (int t = 0; t < m.num_tets(); ++t) u[t] = Eigen::Vector3d(std::sin(k * m.centroid(t).z()), 0, 0);
    const std::vector<double> viscosity(m.num_tets(), mu);
    auto amplitude = [&](const TetVectors& v) {  // least-squares fit of the tets to A sin(k z)
      double num = 0, den = 0;
      for (int t = 0; t < m.num_tets(); ++t) {
        const double s = std::sin(k * m.centroid(t).z());
        num += m.volume[t] * v[t].x() * s;
        den += m.volume[t] * s * s;
      }
      return num / den;
    };
    const double a0 = amplitude(u);
    for (int n = 1; n <= steps; ++n) {
      const double decay = std::exp(-double(n) / steps);
      const ViscousNodes nodes =
          box_held_at(m, [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(decay * std::sin(k * x.z()), 0, 0); });
      apply_viscosity(m, viscosity, m.volume, rho, nodes, h, tight(), u);
    }
    const double rate = -std::log(amplitude(u) / a0);
    std::printf("shear wave, edge %.2f m, %d tets: decay over tau = %.5f (backward Euler %.5f, exact 1)\n", edge,
                m.num_tets(), rate, backward_euler);
    errors.push_back(std::abs(rate - 1));
  }
  EXPECT_LE(errors[0], 0.02);
  EXPECT_LE(errors[1], 0.01);
}

TEST(Viscosity, AFreeBlobKeepsItsRigidRotation) {
  // No Dirichlet node: the free boundary carries no traction. In the stress form a rigid rotation
  // has no strain rate and keeps spinning; the vector-Laplacian form (natural condition du/dn = 0)
  // would brake it to rest (Batty & Bridson 2008, sec. 1). Very viscous: h mu / (rho dx^2) = 1e4.
  const FluidMesh m = unstructured_box(0.1);
  const Eigen::Vector3d omega(0.3, -1.0, 2.0), c = 0.5 * (kLo + kHi);
  TetVectors u(m.num_tets());
  for (int t = 0; t < m.num_tets(); ++t) u[t] = omega.cross(m.centroid(t) - c);
  auto spin = [&](const TetVectors& v) {  // angular momentum / rho about c
    Eigen::Vector3d L = Eigen::Vector3d::Zero();
    for (int t = 0; t < m.num_tets(); ++t) L += m.volume[t] * (m.centroid(t) - c).cross(v[t]);
    return L;
  };
  const Eigen::Vector3d L0 = spin(u);
  const double e0 = energy(m, u);
  const ViscousNodes free_nodes{std::vector<char>(m.num_nodes(), 0), std::vector<Eigen::Vector3d>(m.num_nodes())};
  for (int step = 0; step < 10; ++step)
    apply_viscosity(m, std::vector<double>(m.num_tets(), 100.0), m.volume, 1.0, free_nodes, 1.0, tight(), u);
  const double kept = spin(u).dot(L0) / L0.squaredNorm(), energy_kept = energy(m, u) / e0;
  std::printf("rigid rotation after 10 steps: angular momentum kept %.4f, energy kept %.4f\n", kept, energy_kept);
  EXPECT_GE(kept, 0.97);
  EXPECT_LE(energy_kept, 1.0 + 1e-12);
}

TEST(Viscosity, NoStepAddsEnergyAndATinyViscosityChangesNearlyNothing) {
  const FluidMesh m = unstructured_box(0.1);
  std::mt19937 rng(3);
  std::normal_distribution<double> d(0.0, 1.0);
  TetVectors start(m.num_tets());
  for (auto& v : start) v = Eigen::Vector3d(d(rng), d(rng), d(rng));
  const ViscousNodes walls = box_held_at(m, [](const Eigen::Vector3d&) { return Eigen::Vector3d::Zero(); });
  const ViscousNodes free_nodes{std::vector<char>(m.num_nodes(), 0), std::vector<Eigen::Vector3d>(m.num_nodes())};
  for (const ViscousNodes* nodes : {&walls, &free_nodes})
    for (double mu : {1e-3, 1.0, 1e4})
      for (double h : {1e-3, 1.0, 100.0}) {
        TetVectors u = start;
        double e = energy(m, u);
        for (int step = 0; step < 5; ++step) {
          apply_viscosity(m, std::vector<double>(m.num_tets(), mu), m.volume, 1000.0, *nodes, h, tight(), u);
          const double next = energy(m, u);
          EXPECT_LE(next, e * (1 + 1e-12)) << "mu " << mu << " h " << h << " step " << step;
          e = next;
        }
      }
  // Water (nu = 1e-6 m^2/s) over one 1/60 s step changes u by about h nu / dx^2 of its jumps.
  TetVectors u = start;
  apply_viscosity(m, std::vector<double>(m.num_tets(), 1e-3), m.volume, 1000.0, walls, 1.0 / 60, tight(), u);
  double change = 0, largest = 0;
  for (int t = 0; t < m.num_tets(); ++t) {
    change = std::max(change, (u[t] - start[t]).norm());
    largest = std::max(largest, start[t].norm());
  }
  EXPECT_LE(change, 1e-2 * largest);
}

}  // namespace
}  // namespace tetfsi::fluid
