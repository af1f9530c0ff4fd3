// The bar comparison of Chentanez et al. 2006, Fig. 6 (data/scenes/bar_compare_ci.json): a stiff
// bar on springs between two opposed water jets, run simultaneous at h = 1/30 s, time splitting at
// 1/30 s and time splitting at 1/120 s through `tetfsi run`.
//
// Mechanism. The bar (m_s = ρ_s V, ρ_s = 250 kg/m³) is lighter than the water it has to push
// aside. Time splitting applies the pressure of step n to the solid of step n+1; that pressure
// carries the added-mass reaction to the previous velocity change, −m_a (uⁿ − uⁿ⁻¹)/h, so as
// h → 0 the bar's velocity change is multiplied by −m_a/m_s each step (Causin, Gerbeau & Nobile 2005): an
// oscillation of alternating sign that grows until a fluid tet inverts and the run stops (exit
// code 1, nothing of the failed step written). The one-degree-of-freedom version of the staggered
// step (solid eq. 18 with θ = 1 and the spring k = 1000 N/m implicit, pressure one step late)
// with m_a = 0.47 kg (0.63 ρ_f V) predicts growth factors 1.69 per step at h = 1/30 s and 2.38 at
// 1/120 s (1.84 and 1.57 at 1/30 s for ρ_s = 200 and 300); measured here 1.78 and 2.44 (1.93 and
// 1.56) while |x| < 5 mm. The simultaneous system has the added mass on its left-hand side and
// stays bounded.
//
// The paper's third verdict (splitting stable at 1/120 s) is NOT reproduced, and cannot be in this
// model: both stabilising terms shrink with h. (1) The spring's k h²/2. (2) The advected fluid
// velocity next to the bar forgets a fraction β ≈ min(1, U h / cell) of the bar's previous velocity
// each step, which turns the staggered recursion into z² − (1 − μ) z − μ (1 − β) = 0 (μ = m_a/m_s),
// stable iff μ < 2/(2 − β): splitting tolerates more added mass at LARGER steps. Measured on this
// scene (coupling/README.md): with ρ_s = 450 splitting is stable at 1/30 s and diverges at
// 1/120 s, the reverse of the paper. The lagged-drag mechanism (a damper c ≈ ρ U A applied one
// step late, unstable when c h > 2 (m_s − m_a)) needs a drag our inviscid solver barely has
// (C_d ≈ 0.07 with tet-linear advection) and deflections of about U h, more than a cell without
// remeshing. This test asserts what the model does, verdicts 1 and 2 as in the paper and the
// third as measured, so that a change in either is seen.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

struct BarRun {
  int status = -1;
  std::string log;
  std::vector<double> time, x;  ///< probe rows: time [s], bar centre x displacement [m]
  double max_displacement = 0;  ///< max |u| over all probe rows and components [m]
  bool finite = true;           ///< every probe value finite
};

BarRun run_bar(const TempDir& dir, const std::string& scheme, double h, double density, double end_time = 1.0,
               const std::string& solver = "") {
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/bar_compare_ci.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["coupling"]["scheme"] = scheme;
  scene["simulation"]["dt"] = h;
  scene["simulation"]["end_time"] = end_time;
  scene["solids"][0]["material"]["density"] = density;
  scene["export"] = {{"vtu", false}, {"surfaces", "none"}};
  if (!solver.empty()) scene["coupling"]["solver"] = solver;
  const std::string tag = solver + scheme + "_" + std::to_string(static_cast<int>(std::lround(1 / h))) + "_" +
                          std::to_string(static_cast<int>(density));
  const fs::path file = dir.path() / (tag + ".json"), out = dir.path() / tag;
  std::ofstream(file) << scene.dump(2);
  BarRun r;
  r.log = run_command(std::string(TETFSI_BINARY) + " run " + file.string() + " --out " + out.string() +
                          " --quiet 2>&1",
                      &r.status);
  const Csv probes = read_csv(out / "probes.csv");
  for (std::size_t i = 0; i < probes.rows.size(); ++i) {
    for (double v : probes.rows[i]) r.finite = r.finite && std::isfinite(v);
    r.time.push_back(probes.at(i, "time"));
    r.x.push_back(probes.at(i, "centre_x"));
    for (const char* c : {"centre_x", "centre_y", "centre_z"})
      r.max_displacement = std::max(r.max_displacement, std::abs(probes.at(i, c)));
  }
  return r;
}

/// Diverged the way the staggered added-mass recursion predicts: exit code 1 with the coupled
/// runner's message, finite probes up to the failure, and while the displacement is small
/// (1e-4 m < |x| < 5e-3 m, below a third of a cell: the linear regime, before the mesh update
/// and the nonlinear terms matter) it alternates in sign and grows by > 1.3× per step
/// (geometric mean over at least 4 steps).
void expect_added_mass_divergence(const BarRun& r, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(r.status, 1) << r.log;
  EXPECT_NE(r.log.find("s (time_splitting coupling): "), std::string::npos) << r.log;
  EXPECT_TRUE(r.finite);
  double log_growth = 0;
  int pairs = 0;
  for (std::size_t i = 1; i < r.x.size(); ++i) {
    const double a = std::abs(r.x[i - 1]), b = std::abs(r.x[i]);
    if (a < 1e-4 || a > 5e-3 || b < 1e-4 || b > 5e-3) continue;
    EXPECT_LT(r.x[i] * r.x[i - 1], 0) << "step " << i << ": no sign change";
    log_growth += std::log(b / a);
    ++pairs;
  }
  ASSERT_GE(pairs, 4);
  const double growth = std::exp(log_growth / pairs);
  std::printf("%s: diverged at t = %.4f s, growth per step %.2f over %d steps\n", what.c_str(), r.time.back(), growth,
              pairs);
  EXPECT_GT(growth, 1.3);
}

}  // namespace

TEST(BarCompare, SimultaneousStableSplittingDivergesAtBothSteps) {
  TempDir dir("bar_compare");
  const double cell = 0.0167;  // mesh.edge_length_near_solids of the CI scene [m]

  const BarRun simultaneous = run_bar(dir, "simultaneous", 1.0 / 30, 250);
  EXPECT_EQ(simultaneous.status, 0) << simultaneous.log;
  EXPECT_TRUE(simultaneous.finite);
  // 30 steps of 1/30 s landing exactly on the end time: the driver does not leave a round-off
  // remainder (a sum of thirty 1/30's is 0.99999999999999989; at 3 s that became a 3e-12 s step).
  EXPECT_EQ(simultaneous.time.size(), 31u);
  EXPECT_EQ(simultaneous.time.back(), 1.0);
  // Bounded: seen 1.6e-4 m, a hundredth of a cell, with the 0.01 m/s initial push.
  EXPECT_LT(simultaneous.max_displacement, 0.1 * cell);
  std::printf("simultaneous 1/30 s: max |u| = %.3g m over 1 s\n", simultaneous.max_displacement);

  const BarRun split30 = run_bar(dir, "time_splitting", 1.0 / 30, 250, 3.0);
  expect_added_mass_divergence(split30, "splitting 1/30 s");
  const BarRun split120 = run_bar(dir, "time_splitting", 1.0 / 120, 250);
  expect_added_mass_divergence(split120, "splitting 1/120 s");
  // Smaller steps make splitting fail sooner here (seen 0.075 s against 0.5 s), see above.
  EXPECT_LT(split120.time.back(), split30.time.back());
}

TEST(BarCompare, VerdictsHoldForNeighbouringDensities) {
  // Not a knife edge: ±20% bar density (m_a/m_s from 2.8 to 1.8) gives the same verdicts at
  // h = 1/30 s (the splitting threshold of this scene is near ρ_s ≈ 500 kg/m³ at small steps).
  TempDir dir("bar_compare_neighbours");
  for (double density : {200.0, 300.0}) {
    const BarRun simultaneous = run_bar(dir, "simultaneous", 1.0 / 30, density, 0.5);
    EXPECT_EQ(simultaneous.status, 0) << simultaneous.log;
    EXPECT_LT(simultaneous.max_displacement, 0.1 * 0.0167) << "density " << density;
    // Up to 3 s: a diverging run stops when the bar inverts a fluid tet, which at ρ_s = 300 takes
    // about 1 s (the growth is slower, 1.56× per step); a bounded run would go to the end.
    expect_added_mass_divergence(run_bar(dir, "time_splitting", 1.0 / 30, density, 3.0),
                                 "splitting 1/30 s, density " + std::to_string(static_cast<int>(density)));
  }
}

TEST(BarCompare, FastPathRunsTheLightBarLikeUmfpack) {
  // The light bar's solid block A = M/h + (h/2)K' loses definiteness after the first step (its
  // pre-stress outweighs M/h), so CG on the Schur complement is not defined there; schur_cg goes
  // on with GMRES preconditioned by the first step's SPD factor (coupling/solvers). It must give
  // the reference's trajectory: both solves meet relative residuals of 1e-8, so the bar centres
  // may differ by round-off times the conditioning, far below a thousandth of the motion.
  TempDir dir("bar_fast_path");
  const BarRun fast = run_bar(dir, "simultaneous", 1.0 / 30, 250, 1.0, "schur_cg");
  const BarRun reference = run_bar(dir, "simultaneous", 1.0 / 30, 250, 1.0, "umfpack");
  ASSERT_EQ(fast.status, 0) << fast.log;
  ASSERT_EQ(reference.status, 0) << reference.log;
  ASSERT_EQ(fast.x.size(), reference.x.size());
  ASSERT_GT(reference.max_displacement, 1e-5);
  double worst = 0;
  for (std::size_t i = 0; i < fast.x.size(); ++i) worst = std::max(worst, std::abs(fast.x[i] - reference.x[i]));
  EXPECT_LT(worst, 1e-3 * reference.max_displacement);
  std::printf("schur_cg vs umfpack on the light bar: max |dx| = %.3g m (max |u| %.3g m)\n", worst,
              reference.max_displacement);
}
