// The trapezoidal integrator (Chentanez 2006 appendix) on the linearized cantilever:
// energy conservation (Krenk 2006), period elongation (omega h)^2 / 12 (Krenk 2006), static
// limit of a damped run, prescribed Dirichlet velocities.
#include <gtest/gtest.h>

#include <random>

#include "solid/analysis/linear_analysis.hpp"
#include "solid/integrator/newmark.hpp"
#include "tests/solid/linearized_model.hpp"
#include "apps/fixtures/cantilever.hpp"
#include "solid_test_helpers.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::testing;

namespace {

CantileverSpec small_beam() {
  CantileverSpec s;
  s.cells_along = 20;
  s.cells_across = 2;
  s.material.youngs_modulus = 1e6;
  s.material.poisson_ratio = 0.0;
  s.material.density = 1000;
  return s;
}

}  // namespace

// Linear, undamped: the discrete energy 1/2 u^T M u + 1/2 d^T K' d is conserved to 1e-10
// relative over 1000 steps (Krenk 2006: round-off level).
TEST(Trapezoidal, LinearUndampedConservesEnergy) {
  auto beam = make_cantilever(small_beam());
  LinearizedModel linear(*beam.model);
  NewmarkSettings settings;
  const double time_step = 0.01;
  settings.scheme = NewmarkScheme::kTrapezoidal;
  NewmarkIntegrator integ(linear, settings);
  integ.fix_nodes(beam.clamped_nodes);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> dist(-1e-3, 1e-3);
  Eigen::VectorXd d(3 * linear.num_nodes()), u(3 * linear.num_nodes());
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    d[i] = beam.fixed_dofs[i] ? 0.0 : dist(rng);
    u[i] = dist(rng);
  }
  integ.set_displacement(d);
  integ.set_velocity(u);
  const double e0 = integ.energies().total();
  double worst = 0;
  for (int n = 0; n < 1000; ++n) {
    const auto& st = integ.step(time_step);
    worst = std::max(worst, std::abs(st.total() - e0) / e0);
  }
  EXPECT_LT(worst, 1e-10);
  std::printf("max relative energy drift over 1000 steps: %.3e\n", worst);
}

// Period elongation: started in the first mode, the discrete motion has tan(w_bar h/2) = w h/2,
// T_bar / T = 1 + (w h)^2 / 12 + O((w h)^4) (Krenk 2006; 1.03206,
// 1.00817, 1.00131 at w h = 0.63, 0.31, 0.13).
TEST(Trapezoidal, PeriodElongationFollowsOmegaHSquaredOver12) {
  auto beam = make_cantilever(small_beam());
  LinearizedModel linear(*beam.model);
  const Eigen::VectorXd static_shape = solve_linear_static(linear, beam.fixed_dofs, beam.tip_load({0, 0, -1}));
  const Mode mode = lowest_mode(linear, beam.fixed_dofs, static_shape);
  for (double wh : {0.63, 0.31, 0.13}) {
    NewmarkSettings settings;
    const double time_step = wh / mode.omega;
    settings.scheme = NewmarkScheme::kTrapezoidal;
    NewmarkIntegrator integ(linear, settings);
    integ.fix_nodes(beam.clamped_nodes);
    integ.set_displacement(1e-3 * mode.shape);
    std::vector<double> q{modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement())};
    const int steps = static_cast<int>(4 * 2 * M_PI / wh);  // four periods
    for (int n = 0; n < steps; ++n) {
      integ.step(time_step);
      q.push_back(modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement()));
    }
    const double ratio = mode.omega / sampled_frequency(q, time_step);  // T_bar / T
    const double exact = mode.omega / trapezoidal_frequency(mode.omega, time_step);
    std::printf("w h = %.2f: T_bar/T = %.6f (exact %.6f, 1 + (w h)^2/12 = %.6f)\n", wh, ratio, exact, 1 + wh * wh / 12);
    EXPECT_NEAR(ratio, exact, 1e-5) << "w h = " << wh;
    // Leading term (w h)^2 / 12; the next term is -(w h)^4 / ... so allow 6% of the elongation.
    EXPECT_NEAR(ratio - 1, wh * wh / 12, 0.06 * wh * wh / 12) << "w h = " << wh;
    // No amplitude decay: the peak of |q| over the last period equals the initial amplitude.
    double peak = 0;
    for (size_t n = q.size() - static_cast<size_t>(2 * M_PI / wh) - 1; n < q.size(); ++n) peak = std::max(peak, std::abs(q[n]));
    EXPECT_LE(peak, q[0] * (1 + 1e-9));
  }
}

// The paper's scheme as printed (Newmark beta = 1/2, gamma = 1, eq. 18): on a linear undamped
// mode, with s = (omega h)^2 / 2, the modal coordinate obeys (1 + s) q_{n+1} - (2 - s) q_n +
// q_{n-1} = 0 [calc from eqs. 12-14]: amplitude factor 1/sqrt(1 + s) per step, so the energy
// decays monotonically (never grows).
TEST(Trapezoidal, ChentanezSchemeMatchesItsAmplificationFactor) {
  auto beam = make_cantilever(small_beam());
  LinearizedModel linear(*beam.model);
  const Eigen::VectorXd static_shape = solve_linear_static(linear, beam.fixed_dofs, beam.tip_load({0, 0, -1}));
  const Mode mode = lowest_mode(linear, beam.fixed_dofs, static_shape);
  for (double wh : {0.3, 0.1}) {
    NewmarkSettings settings;
    const double time_step = wh / mode.omega;
    settings.scheme = NewmarkScheme::kChentanez;
    NewmarkIntegrator integ(linear, settings);
    integ.fix_nodes(beam.clamped_nodes);
    integ.set_displacement(1e-3 * mode.shape);
    std::vector<double> q{modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement())};
    double energy = integ.energies().total();
    for (int n = 0; n < 200; ++n) {
      const double e = integ.step(time_step).total();
      EXPECT_LE(e, energy * (1 + 1e-12));
      energy = e;
      q.push_back(modal_coordinate(mode.shape, linear.lumped_masses(), integ.displacement()));
    }
    const auto [a, b] = fit_recurrence(q);
    const double s = 0.5 * wh * wh;
    EXPECT_NEAR(a, (2 - s) / (1 + s), 1e-8) << "w h = " << wh;
    EXPECT_NEAR(b, -1 / (1 + s), 1e-8) << "w h = " << wh;
  }
}

// Heavily damped run under gravity and a tip load settles to the linear static solution.
TEST(Trapezoidal, DampedRunSettlesToLinearStatics) {
  auto beam = make_cantilever(small_beam());
  LinearizedModel linear(*beam.model);
  NewmarkSettings settings;
  const double time_step = 0.05;
  settings.scheme = NewmarkScheme::kChentanez;  // damps the stiff modes (theta = 1/2 would not)
  settings.rayleigh_alpha = 8.0;
  settings.rayleigh_beta = 0.01;
  settings.gravity = {0, 0, -9.81};
  NewmarkIntegrator integ(linear, settings);
  integ.fix_nodes(beam.clamped_nodes);
  const Eigen::VectorXd tip = beam.tip_load({0, 0.5, 0});
  integ.set_external_forces(tip);
  for (int n = 0; n < 400; ++n) integ.step(time_step);
  Eigen::VectorXd f = tip;
  for (int v = 0; v < linear.num_nodes(); ++v) f[3 * v + 2] += -9.81 * linear.lumped_masses()[v];
  const Eigen::VectorXd d_static = solve_linear_static(linear, beam.fixed_dofs, f);
  EXPECT_LT((integ.displacement() - d_static).norm(), 1e-8 * d_static.norm());
  EXPECT_LT(integ.velocity().norm(), 1e-8 * d_static.norm());
}

TEST(Trapezoidal, PrescribedVelocityAndSolverChoice) {
  auto beam = make_cantilever(small_beam());
  for (auto kind : {SolverKind::kCholmod, SolverKind::kConjugateGradient, SolverKind::kConjugateGradientIC}) {
    NewmarkSettings settings;
    const double time_step = 0.01;
    settings.solver = kind;
    NewmarkIntegrator integ(*beam.model, settings);
    const Eigen::Vector3d v(0.1, 0, 0);
    integ.fix_nodes(beam.clamped_nodes, v);
    for (int n = 0; n < 10; ++n) integ.step(time_step);
    for (int node : beam.clamped_nodes)
      EXPECT_NEAR((integ.displacement().segment<3>(3 * node) - 10 * 0.01 * v).norm(), 0, 1e-14);
    EXPECT_GE(integ.last_stats().solver_iterations, 1);
    // The free end starts to follow; nothing non-finite.
    EXPECT_TRUE(integ.displacement().allFinite());
  }
}

// fix_components: the root held in y and z only is a frictionless support for a load along x.
// Under gravity g e_x the beam then falls freely along x as a rigid body, d_x = g t^2 / 2 at every
// node (exact for both schemes: no strain, u^{n+1} = u^n + h g), with y and z of the root still 0;
// held in all components the root stops it (the tip moves less than a tenth of g t^2 / 2).
TEST(Trapezoidal, RootHeldInTwoComponentsSlidesFreelyInTheThird) {
  auto beam = make_cantilever(small_beam());
  for (bool all : {false, true}) {
    NewmarkSettings settings;
    const double time_step = 0.01;
    settings.gravity = {3.0, 0, 0};
    NewmarkIntegrator integ(*beam.model, settings);
    integ.fix_components(beam.clamped_nodes, {all, true, true});
    for (int n = 0; n < 20; ++n) integ.step(time_step);
    const double t = 20 * 0.01, fall = 0.5 * 3.0 * t * t;
    const auto& d = integ.displacement();
    for (int node : beam.clamped_nodes) {
      EXPECT_EQ(d[3 * node + 1], 0.0);
      EXPECT_EQ(d[3 * node + 2], 0.0);
    }
    if (!all) {
      for (int node = 0; node < beam.model->num_nodes(); ++node)
        ASSERT_NEAR(d[3 * node], fall, 1e-12 * fall) << "node " << node;
      EXPECT_LT(d.cwiseAbs().maxCoeff(), fall * (1 + 1e-12));  // nothing moves across
    } else {
      EXPECT_LT(beam.tip_displacement(d, 0), 0.1 * fall);
    }
  }
}

// Springs to fixed anchors: a body on springs k_i = c m_i moves rigidly with omega = sqrt(c)
// (spring-mounted body, f = sqrt(k/m) / 2 pi, without fluid); the
// trapezoidal scheme shows exactly its discrete frequency 2/h atan(omega h / 2).
TEST(Trapezoidal, SpringMountedBodyOscillatesAtSqrtKOverM) {
  auto beam = make_cantilever(small_beam());
  const double c = 400.0;  // omega = 20 rad/s
  NewmarkSettings settings;
  const double time_step = 0.005;
  settings.scheme = NewmarkScheme::kTrapezoidal;
  NewmarkIntegrator integ(*beam.model, settings);
  const auto& X = beam.model->reference_positions();
  const auto& m = beam.model->lumped_masses();
  for (int v = 0; v < beam.model->num_nodes(); ++v) integ.add_spring({v, X.segment<3>(3 * v), c * m[v]});
  integ.set_uniform_velocity({0, 0, 0.01});
  std::vector<double> z{0.0};
  for (int n = 0; n < 150; ++n) {
    integ.step(time_step);
    z.push_back(m.dot(Eigen::VectorXd(integ.displacement()(Eigen::seqN(2, m.size(), 3)))) / m.sum());
  }
  EXPECT_NEAR(sampled_frequency(z, time_step) / trapezoidal_frequency(std::sqrt(c), time_step), 1.0,
              1e-9);
  // Energy (kinetic + spring + strain) is conserved by the trapezoidal scheme.
  EXPECT_NEAR(integ.energies().total(), 0.5 * m.sum() * 1e-4, 1e-10 * m.sum() * 1e-4);
}
