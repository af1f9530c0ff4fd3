// A short, readable MPM step for linear-elastic particles (Lian, Liu & Zhang 2014, section 6,
// USF form; equal steps; free grid faces), written with plain loops over particles and nodes, and
// the fast per-cell passes of MpmSolver (mpm/particles/mpm_solver.hpp) tested against it. The
// reference step is the algorithm of mpm_solver.hpp and nothing more:
//   1. particle-to-grid: m_I = sum_p N_Ip m_p, p_I = sum_p N_Ip m_p v_p            (eqs. 60, 61)
//   2. grid velocity v_I = p_I / m_I; velocity gradient L_p = sum_I v_I (grad N_Ip)^T (eqs. 62, 63)
//   3. stress: sigma += h (lambda tr D I + 2 G D + W sigma - sigma W), rho *= exp(-h tr D)
//                                                                                 (eqs. 22, 25)
//   4. nodal force f_I = -sum_p V_p sigma_p grad N_Ip + m_I g; p_I' = p_I + h f_I (eqs. 17, 18, 64)
//   5. grid-to-particle: v_p += sum_I N_Ip (p_I' - p_I) / m_I, x_p += h sum_I N_Ip p_I' / m_I
//                                                                                 (eqs. 65, 19)
// The two differ only in the order of the sums (and exp against its Taylor polynomial), so they
// must agree to round-off.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <vector>

#include "mpm/particles/mpm_solver.hpp"

namespace tetfsi::mpm {
namespace {

/// One reference step of length h of elastic particles P on grid g (material 0 of `mat`).
void reference_step(const Grid& g, const Material& mat, const Vec3& gravity, double h, Particles& P) {
  const double lambda = mat.lame_lambda(), two_G = 2 * mat.shear_modulus();
  const std::int64_t nodes = g.num_nodes();
  std::vector<double> m(nodes, 0.0);
  std::vector<Vec3> p(nodes, Vec3::Zero()), f(nodes, Vec3::Zero());

  // The 8 nodes of a particle's cell with their trilinear weights N and gradients grad N.
  auto for_each_node = [&](const Vec3& x, auto&& visit) {
    int base[3];
    double w[3][2], dw[3][2];
    for (int a = 0; a < 3; ++a) {
      const double s = (x[a] - g.lo[a]) / g.dx;
      base[a] = static_cast<int>(std::floor(s));
      const double frac = s - base[a];
      w[a][0] = 1 - frac, w[a][1] = frac;
      dw[a][0] = -1 / g.dx, dw[a][1] = 1 / g.dx;
    }
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          const double N = w[0][i] * w[1][j] * w[2][k];
          const Vec3 dN(dw[0][i] * w[1][j] * w[2][k], w[0][i] * dw[1][j] * w[2][k], w[0][i] * w[1][j] * dw[2][k]);
          visit(g.node_index(base[0] + i, base[1] + j, base[2] + k), N, dN);
        }
  };

  // 1. Particle to grid.
  for (std::size_t q = 0; q < P.size(); ++q)
    for_each_node(P.x[q], [&](std::int64_t I, double N, const Vec3&) {
      m[I] += N * P.mass[q];
      p[I] += N * P.mass[q] * P.v[q];
    });
  std::vector<Vec3> v(nodes, Vec3::Zero());
  for (std::int64_t I = 0; I < nodes; ++I)
    if (m[I] > 0) v[I] = p[I] / m[I];

  // 2, 3, 4. Velocity gradient, stress update, internal forces.
  for (std::size_t q = 0; q < P.size(); ++q) {
    Mat3 L = Mat3::Zero();
    for_each_node(P.x[q], [&](std::int64_t I, double, const Vec3& dN) { L += v[I] * dN.transpose(); });
    const Mat3 D = 0.5 * (L + L.transpose()), W = 0.5 * (L - L.transpose());
    Mat3& sigma = P.stress[q];
    sigma += h * (lambda * D.trace() * Mat3::Identity() + two_G * D + W * sigma - sigma * W);
    P.rho[q] *= std::exp(-h * D.trace());
    const double V = P.mass[q] / P.rho[q];
    for_each_node(P.x[q], [&](std::int64_t I, double, const Vec3& dN) { f[I] -= V * sigma * dN; });
  }
  std::vector<Vec3> p_new(nodes);
  for (std::int64_t I = 0; I < nodes; ++I) p_new[I] = p[I] + h * (f[I] + m[I] * gravity);

  // 5. Grid to particle.
  for (std::size_t q = 0; q < P.size(); ++q) {
    Vec3 dv = Vec3::Zero(), vel = Vec3::Zero();
    for_each_node(P.x[q], [&](std::int64_t I, double N, const Vec3&) {
      if (m[I] <= 0) return;
      dv += N * (p_new[I] - p[I]) / m[I];
      vel += N * p_new[I] / m[I];
    });
    P.v[q] += dv;
    P.x[q] += h * vel;
  }
}

TEST(MpmReference, FastPassesMatchTheReferenceStep) {
  // An elastic ball (r = 0.2 m, 2 x 2 x 2 particles per cell of 0.05 m) translating, spinning and
  // expanding, v = v0 + w x (x - c) + eps (x - c), under gravity, 20 steps of half its critical step.
  const double dx = 0.05, r = 0.2, rho = 1000;
  const Material mat = Material::linear_elastic(rho, 1e5, 0.3);
  const Vec3 gravity(0, -9.81, 0), v0(0.3, -0.1, 0.2), w(0.5, 1.0, -2.0);
  const double eps = 0.4;
  Grid g = Grid::covering(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5), dx);
  Particles P;
  sample_lattice(P, Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5), dx / 2, rho, 0, Vec3::Zero(), 0,
                 [&](const Vec3& x) { return x.norm() < r; });
  double vmax = 0;
  for (std::size_t q = 0; q < P.size(); ++q) {
    P.v[q] = v0 + w.cross(P.x[q]) + eps * P.x[q];
    vmax = std::max(vmax, P.v[q].norm());
  }
  MpmOptions options;
  options.gravity = gravity;
  MpmSolver fast(g, {mat}, P, options);
  Particles ref = P;
  const double c = std::sqrt((mat.lame_lambda() + 2 * mat.shear_modulus()) / rho);
  const double h = 0.5 * dx / (c + vmax);
  double mass = 0;
  Vec3 momentum0 = Vec3::Zero();
  for (std::size_t q = 0; q < P.size(); ++q) mass += P.mass[q], momentum0 += P.mass[q] * P.v[q];
  const int steps = 20;
  for (int n = 0; n < steps; ++n) {
    fast.step(h);
    reference_step(g, mat, gravity, h, ref);
  }

  // The reference conserves momentum: p(t) = p(0) + M g t, to round-off.
  Vec3 momentum = Vec3::Zero();
  for (std::size_t q = 0; q < ref.size(); ++q) momentum += ref.mass[q] * ref.v[q];
  const Vec3 exact = momentum0 + mass * gravity * (steps * h);
  EXPECT_LT((momentum - exact).norm(), 1e-12 * mass * vmax);

  // The fast passes give the reference's state to round-off.
  const Particles& F = fast.particles();
  double sigma_scale = 0;
  for (const auto& s : ref.stress) sigma_scale = std::max(sigma_scale, s.norm());
  double dx_err = 0, dv_err = 0, ds_err = 0, drho_err = 0;
  for (std::size_t q = 0; q < ref.size(); ++q) {
    dx_err = std::max(dx_err, (F.x[q] - ref.x[q]).norm() / dx);
    dv_err = std::max(dv_err, (F.v[q] - ref.v[q]).norm() / vmax);
    ds_err = std::max(ds_err, (F.stress[q] - ref.stress[q]).norm() / sigma_scale);
    drho_err = std::max(drho_err, std::abs(F.rho[q] - ref.rho[q]) / rho);
  }
  std::printf("[reference step] %zu particles, %d steps of %.3e s, stress up to %.3e Pa: max relative "
              "difference x %.2e, v %.2e, sigma %.2e, rho %.2e\n",
              ref.size(), steps, h, sigma_scale, dx_err, dv_err, ds_err, drho_err);
  ASSERT_GT(sigma_scale, 0.0);
  EXPECT_LT(dx_err, 1e-12);
  EXPECT_LT(dv_err, 1e-12);
  EXPECT_LT(ds_err, 1e-12);
  EXPECT_LT(drho_err, 1e-12);
}

}  // namespace
}  // namespace tetfsi::mpm
