// Cantilever against Euler-Bernoulli beam theory: static tip deflection and first
// bending frequency converge with refinement; a Rayleigh-damped run decays at
// zeta = alpha / (2 omega) + beta omega / 2 (Rayleigh damping) within 5%.
// Beam: L = 1 m, 0.1 m x 0.1 m (L/b = 10), E = 1 MPa, nu = 0, rho = 1000 kg/m^3; n x m x m
// cells with n = 10 m, 6 tets per cell. Constant-strain tets are stiff in bending, so the coarse
// test meshes are far from the reference; the benchmark (apps/bench/solid) runs finer levels.
#include <gtest/gtest.h>

#include "solid/analysis/linear_analysis.hpp"
#include "solid/integrator/newmark.hpp"
#include "tests/solid/linearized_model.hpp"
#include "apps/fixtures/cantilever.hpp"
#include "solid_test_helpers.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::testing;

namespace {

CantileverSpec beam_spec(int m) { return slender_cantilever_spec(m); }

struct Level {
  double deflection_error, omega_error, omega;
};

Level analyse(int m) {
  auto beam = make_cantilever(beam_spec(m));
  const double P = 1e-3;  // small: linear regime
  const Eigen::VectorXd d = solve_linear_static(*beam.model, beam.fixed_dofs, beam.tip_load({0, 0, -P}));
  const double w = -beam.tip_displacement(d, 2);
  const Mode mode = lowest_mode(*beam.model, beam.fixed_dofs, d, 1e-10);
  return {w / beam.euler_bernoulli_deflection(P) - 1, mode.omega / beam.euler_bernoulli_omega1() - 1, mode.omega};
}

}  // namespace

TEST(Cantilever, StaticDeflectionAndFrequencyConvergeToEulerBernoulli) {
  const Level l2 = analyse(2), l3 = analyse(3), l4 = analyse(4);
  std::printf("tip deflection error: %.4f %.4f %.4f; omega1 error: %.4f %.4f %.4f (m = 2, 3, 4)\n",
              l2.deflection_error, l3.deflection_error, l4.deflection_error, l2.omega_error, l3.omega_error,
              l4.omega_error);
  // Too stiff, monotonically less so with refinement, roughly second order.
  EXPECT_LT(l2.deflection_error, l3.deflection_error);
  EXPECT_LT(l3.deflection_error, l4.deflection_error);
  EXPECT_LT(l4.deflection_error, 0.0);
  EXPECT_LT(std::abs(l4.deflection_error), 0.5 * std::abs(l2.deflection_error));
  EXPECT_LT(std::abs(l4.deflection_error), 0.20);  // finest test level, 3840 tets
  EXPECT_GT(l2.omega_error, l3.omega_error);
  EXPECT_GT(l3.omega_error, l4.omega_error);
  EXPECT_GT(l4.omega_error, 0.0);
  EXPECT_LT(l4.omega_error, 0.5 * l2.omega_error);
  EXPECT_LT(l4.omega_error, 0.08);
}

// The integrator reproduces the discrete first mode: started in the mode shape, the measured
// frequency equals the trapezoidal image 2/h atan(omega h / 2) of the eigenvalue.
TEST(Cantilever, DynamicFrequencyMatchesModalAnalysis) {
  auto beam = make_cantilever(beam_spec(2));
  LinearizedModel linear(*beam.model);
  const Eigen::VectorXd d = solve_linear_static(linear, beam.fixed_dofs, beam.tip_load({0, 0, -1}));
  const Mode mode = lowest_mode(linear, beam.fixed_dofs, d);
  NewmarkSettings settings;
  const double time_step = 0.05 / mode.omega;
  settings.scheme = NewmarkScheme::kTrapezoidal;
  NewmarkIntegrator integ(linear, settings);
  integ.fix_nodes(beam.clamped_nodes);
  integ.set_displacement(1e-3 * mode.shape);
  std::vector<double> q{modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement())};
  for (int n = 0; n < 400; ++n) {
    integ.step(time_step);
    q.push_back(modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement()));
  }
  EXPECT_NEAR(sampled_frequency(q, time_step) / trapezoidal_frequency(mode.omega, time_step), 1.0,
              1e-6);
}

// Rayleigh damping: log decrement of the first-mode amplitude gives zeta within 5% of
// alpha / (2 omega) + beta omega / 2 (Rayleigh damping). With Chentanez et al. 2006's scheme (eq. 18) the
// numerical damping of Newmark gamma = 1, about omega h / 4 [calc], adds to it.
namespace {
double measured_damping_ratio(NewmarkScheme scheme, double& expected) {
  auto beam = make_cantilever(beam_spec(2));
  LinearizedModel linear(*beam.model);
  const Eigen::VectorXd d = solve_linear_static(linear, beam.fixed_dofs, beam.tip_load({0, 0, -1}));
  const Mode mode = lowest_mode(linear, beam.fixed_dofs, d);
  NewmarkSettings settings;
  settings.rayleigh_alpha = 0.02 * mode.omega;  // contributes zeta = 0.01
  settings.rayleigh_beta = 0.02 / mode.omega;   // contributes zeta = 0.01
  double zeta = settings.rayleigh_alpha / (2 * mode.omega) + settings.rayleigh_beta * mode.omega / 2;
  const double period = 2 * M_PI / mode.omega;
  const double time_step = period / 100;
  settings.scheme = scheme;
  if (scheme == NewmarkScheme::kChentanez) zeta += 0.25 * mode.omega * time_step;
  expected = zeta;
  NewmarkIntegrator integ(linear, settings);
  integ.fix_nodes(beam.clamped_nodes);
  integ.set_displacement(1e-3 * mode.shape);
  std::vector<double> q{modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement())};
  for (int n = 0; n < 600; ++n) {
    integ.step(time_step);
    q.push_back(modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement()));
  }
  // Positive peaks, refined by a parabola through the three samples around each maximum.
  std::vector<double> peaks;
  for (size_t n = 1; n + 1 < q.size(); ++n)
    if (q[n] > q[n - 1] && q[n] >= q[n + 1] && q[n] > 0) {
      const double a = 0.5 * (q[n - 1] + q[n + 1]) - q[n], b = 0.5 * (q[n + 1] - q[n - 1]);
      peaks.push_back(q[n] - b * b / (4 * a));
    }
  if (peaks.size() < 4) return 0.0;
  const int cycles = static_cast<int>(peaks.size()) - 1;
  const double delta = std::log(peaks.front() / peaks.back()) / cycles;
  return delta / std::sqrt(4 * M_PI * M_PI + delta * delta);
}
}  // namespace

TEST(Cantilever, RayleighDampedDecayMatchesModalDampingRatio) {
  for (auto scheme : {NewmarkScheme::kTrapezoidal, NewmarkScheme::kChentanez}) {
    double expected = 0;
    const double measured = measured_damping_ratio(scheme, expected);
    std::printf("scheme %d: zeta measured %.6f, expected %.6f\n", static_cast<int>(scheme), measured, expected);
    EXPECT_NEAR(measured, expected, 0.05 * expected);
  }
}
