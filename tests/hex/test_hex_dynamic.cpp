// The hex8 model inside the tet solid's trapezoidal integrator (solid/integrator/newmark.hpp,
// Chentanez et al. 2006 appendix eqs. 9-18), through the ElasticModel interface: no second copy.
// Validation: free vibration of a clamped cantilever against Euler-Bernoulli (beta_1 L = 1.875104):
//   omega_1 = (beta_1 L)^2 sqrt(EI / (rho A L^4)),  (beta_1 L)^2 = 3.516015.
#include <gtest/gtest.h>

#include <cmath>

#include "solid/hex/block_mesh.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/hex_model.hpp"
#include "solid/integrator/newmark.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::hex;

// Released from the static deflection under a small tip load (tip deflection 1e-3 L: linear
// range), 100 x 2 x 1 hexes, 60 steps per period. Expected deviations: shear locking makes the
// beam ~2 % stiffer ((G/E)(dx/h)^2, dx/h = 0.2) -> ~ +1 % in frequency; trapezoidal period
// elongation (omega h)^2/12 = 0.1 %; lumped mass slightly lowers the frequency. Tolerance 2.5 %.
TEST(HexDynamic, CantileverFirstFrequencyMatchesEulerBernoulli) {
  const double L = 1, h = 0.05, b = 0.05;
  Material m;
  m.youngs_modulus = 1e7;
  m.poisson_ratio = 0.0;
  m.density = 1000;
  const auto mesh = block_mesh({0, 0, 0}, {L, h, b}, 100, 2, 1);
  const HexModel model(mesh, m);
  const double EI = m.youngs_modulus * b * h * h * h / 12, rhoA = m.density * b * h;
  const double omega = 3.516015 * std::sqrt(EI / (rhoA * L * L * L * L));
  const double period = 2 * M_PI / omega;

  const auto root = nodes_in_box(mesh, {0, 0, 0}, {0, h, b});
  const auto end = nodes_in_box(mesh, {L, 0, 0}, {L, h, b});
  BoundaryConditions bc;
  fix_nodes(bc, root);
  const double P = 3 * EI * 1e-3 / (L * L * L);  // tip deflection ~ 1e-3 L
  add_nodal_force(bc, model.num_nodes(), end, {0, P / static_cast<double>(end.size()), 0});
  StaticOptions opt;
  opt.load_steps = 1;
  const auto deflected = solve_static(model, bc, opt);

  tetfsi::solid::NewmarkSettings settings;
  settings.scheme = tetfsi::solid::NewmarkScheme::kTrapezoidal;  // beta = 1/4, gamma = 1/2
  const double time_step = period / 60;
  tetfsi::solid::NewmarkIntegrator integ(model, settings);
  integ.fix_nodes(root);
  integ.set_displacement(deflected.displacement);
  auto tip_y = [&]() {
    double y = 0;
    for (int v : end) y += integ.displacement()(3 * v + 1);
    return y / static_cast<double>(end.size());
  };
  const double e0 = integ.energies().total();
  double previous = tip_y(), previous_time = 0;
  std::vector<double> crossings;  // downward zero crossings of the tip deflection
  double worst_drift = 0;
  while (integ.time() < 3.2 * period) {
    const auto& st = integ.step(time_step);
    worst_drift = std::max(worst_drift, std::abs(st.total() - e0) / e0);
    const double y = tip_y();
    if (previous > 0 && y <= 0) crossings.push_back(previous_time + (integ.time() - previous_time) * previous / (previous - y));
    previous = y;
    previous_time = integ.time();
  }
  ASSERT_GE(crossings.size(), 3u);
  const double measured = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  std::printf("period: measured %.5f s, Euler-Bernoulli %.5f s (rel %.3e), energy drift %.2e\n", measured, period,
              measured / period - 1, worst_drift);
  EXPECT_NEAR(measured / period, 1.0, 0.025);
  // Small amplitude -> nearly linear -> the trapezoidal rule nearly conserves energy (benchmarks 3.6).
  EXPECT_LT(worst_drift, 1e-3);
}
