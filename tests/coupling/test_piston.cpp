// Piston in a fluid-filled tube (Causin, Gerbeau & Nobile 2005): the simultaneous system oscillates at
// f = (1/2π)√(k/(m_s + ρ_f L A)); time splitting blows up when ρ_f L A / m_s > 1 and stays
// bounded below it, for any time step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "apps/fixtures/piston_fixture.hpp"

using namespace tetfsi;
using test::PistonSetup;

namespace {

/// Runs `periods` exact periods; returns the measured frequency from upward zero crossings of the
/// plug displacement (linear interpolation between steps) and the largest |x| seen.
struct PistonRun {
  double frequency = 0;
  double max_amplitude = 0;
  double energy_drift = 0;  ///< max |E(t) - E(first step)| / E(first step)
  double final_energy_loss = 0;  ///< 1 - E(last step) / E(first step)
  bool diverged = false;
};

PistonRun run_piston(const PistonSetup& s, double periods, double v0 = 1e-3) {
  auto stepper = test::make_piston(s, v0);
  const int steps = static_cast<int>(periods / (s.exact_frequency() * s.time_step));
  std::vector<double> crossings;
  double prev = 0;
  PistonRun run;
  double e0 = -1;
  for (int k = 0; k < steps; ++k) {
    coupling::CoupledStepReport rep;
    try {
      rep = stepper->step(s.time_step);
    } catch (const std::exception& e) {
      if (std::getenv("TETFSI_TEST_VERBOSE")) std::fprintf(stderr, "step %d: %s\n", k, e.what());
      run.diverged = true;  // detected and reported as an error: counts as blown up
      return run;
    }
    const double x = test::plug_displacement(*stepper);
    if (std::getenv("TETFSI_TEST_VERBOSE") && k % 10 == 0)
      std::fprintf(stderr, "t=%.3f x=%.3e Ef=%.4e Ek=%.4e Es=%.4e Esp=%.4e tot=%.5e\n", stepper->time(), x,
                   rep.fluid_kinetic, rep.solid_kinetic, rep.solid_strain, rep.spring_energy, rep.total_energy());
    if (e0 < 0) e0 = rep.total_energy();
    run.energy_drift = std::max(run.energy_drift, std::abs(rep.total_energy() - e0) / e0);
    run.max_amplitude = std::max(run.max_amplitude, std::abs(x));
    run.final_energy_loss = 1 - rep.total_energy() / e0;
    if (k > 0 && prev < 0 && x >= 0) crossings.push_back(stepper->time() - s.time_step * x / (x - prev));
    prev = x;
  }
  if (crossings.size() >= 2)
    run.frequency = (crossings.size() - 1) / (crossings.back() - crossings.front());
  return run;
}

}  // namespace

TEST(Piston, SimultaneousCouplingOscillatesAtAddedMassFrequency) {
  for (double fluid_density : {1000.0, 50.0}) {  // m_a/m_s = 10 and 0.5
    PistonSetup s;
    s.fluid_density = fluid_density;
    const PistonRun run = run_piston(s, 4.5);
    ASSERT_FALSE(run.diverged);
    const double f = s.exact_frequency();
    std::printf("piston m_a/m_s=%.1f: f=%.6f Hz, exact %.6f Hz, rel. error %.2e, energy drift %.2e\n",
                s.added_mass() / s.solid_mass(), run.frequency, f, run.frequency / f - 1, run.energy_drift);
    EXPECT_NEAR(run.frequency, f, 0.01 * f) << "rho_f = " << fluid_density << ", m_a/m_s = "
                                            << s.added_mass() / s.solid_mass();
    // Undamped, no gravity, p = 0 at the open end: the coupled step conserves
    // fluid kinetic + plug kinetic + spring energy up to the trapezoidal rule's accuracy.
    EXPECT_LT(run.energy_drift, 1e-3) << "rho_f = " << fluid_density;
  }
}

TEST(Piston, PaperSchemeAsPrintedKeepsTheFrequencyButDampsAtOmegaHOverFour) {
  // Eq. (18) as printed is Newmark β = ½, γ = 1: the amplitude decays by 1/√(1 + (ωh)²/2) a step
  // (solid/integrator/newmark.hpp), so the energy by 1/(1 + (ωh)²/2), while the frequency moves
  // by O((ωh)²) only.
  PistonSetup s;
  s.newmark = solid::NewmarkScheme::kChentanez;
  const double periods = 3.5;
  const PistonRun run = run_piston(s, periods);
  ASSERT_FALSE(run.diverged);
  const double f = s.exact_frequency();
  EXPECT_NEAR(run.frequency, f, 0.01 * f);
  const double wh = 2 * M_PI * f * s.time_step;
  const int steps = static_cast<int>(periods / (f * s.time_step));
  const double expected_loss = 1 - std::pow(1 + wh * wh / 2, -(steps - 1));
  std::printf("paper scheme: f rel. error %.2e, energy loss %.4f (predicted %.4f)\n", run.frequency / f - 1,
              run.final_energy_loss, expected_loss);
  EXPECT_NEAR(run.final_energy_loss, expected_loss, 0.1 * expected_loss);
}

TEST(Piston, TimeSplittingIsUnstableExactlyWhenAddedMassExceedsSolidMass) {
  for (double h : {1.0 / 100, 1.0 / 400}) {
    PistonSetup light;  // m_a/m_s = 2.5
    light.fluid_density = 250;
    light.time_step = h;
    light.scheme = coupling::CouplingScheme::kTimeSplitting;
    const PistonRun unstable = run_piston(light, 3.0);
    EXPECT_TRUE(unstable.diverged || unstable.max_amplitude > 1e3 * (1e-3 / (2 * M_PI * light.exact_frequency())))
        << "h = " << h << ": time splitting stayed bounded at m_a/m_s = 2.5";

    PistonSetup heavy;  // m_a/m_s = 0.5
    heavy.fluid_density = 50;
    heavy.time_step = h;
    heavy.scheme = coupling::CouplingScheme::kTimeSplitting;
    const PistonRun stable = run_piston(heavy, 3.0);
    ASSERT_FALSE(stable.diverged) << "h = " << h;
    const double amplitude = 1e-3 / (2 * M_PI * heavy.exact_frequency());
    EXPECT_LT(stable.max_amplitude, 2 * amplitude) << "h = " << h << ": time splitting grew at m_a/m_s = 0.5";
  }
}

TEST(Piston, ThreeSolversAgreeOnTheSameStep) {
  std::vector<Eigen::VectorXd> velocities;
  for (auto kind : {coupling::CoupledSolverKind::Umfpack, coupling::CoupledSolverKind::BiCGSTAB,
                    coupling::CoupledSolverKind::SchurCG}) {
    PistonSetup s;
    s.solver = kind;
    auto stepper = test::make_piston(s, 1e-3);
    const auto rep = stepper->step(s.time_step);
    EXPECT_LE(rep.solve.residual.max(), 1e-10) << rep.solve.solver;
    velocities.push_back(stepper->solid(0).velocity());
  }
  for (std::size_t k = 1; k < velocities.size(); ++k)
    EXPECT_LT((velocities[k] - velocities[0]).norm(), 1e-8 * velocities[0].norm());
}
