// A spherical linear membrane inflated by ideal gas (data/scenes/balloon_ci.json, an octant with
// three symmetry planes) through `tetfsi run`: the settled radius against the static equilibrium
//   2 N / R = p(R) - p_ext,  N = E h / (1 - nu) (R / R0 - 1),  p = p0 (V_gas0 / V)^gamma_eff,
// whose adiabatic (gamma_eff = gamma) and isothermal (gamma_eff = 1) roots bracket the damped
// result: viscous heating puts the gas above its isentrope, and no heat leaves it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace tetfsi::test;

namespace {

const fs::path kScenes = fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes";

/// The balloon's equilibrium in the stretch lambda = R / R0 of the membrane's own rest shape.
struct Balloon {
  double R0, Eh, nu, p0, p_ext, gamma;
  double fill;  ///< V_gas0 / V_membrane0: the particle lattice's volume over the faceted membrane's
  /// Strain measure of N: the reference's engineering strain l - 1, or (for comparison only) the
  /// log strain ln l that the membrane's rate form (stress += C D dt, constant thickness) integrates.
  bool log_strain = false;

  /// Membrane tension term minus net gas pressure at stretch l; increasing in l.
  double residual(double l, double gamma_eff) const {
    const double N = Eh / (1 - nu) * (log_strain ? std::log(l) : l - 1);
    return 2 * N / (R0 * l) - (p0 * std::pow(fill / (l * l * l), gamma_eff) - p_ext);
  }
  /// Root of residual by bisection on [0.5, 3].
  double stretch(double gamma_eff) const {
    double lo = 0.5, hi = 3.0;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (residual(mid, gamma_eff) > 0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

}  // namespace

TEST(MpmBalloon, CiSettlesBetweenTheAdiabaticAndIsothermalEquilibria) {
  const fs::path scene_file = kScenes / "balloon_ci.json";
  std::ifstream in(scene_file);
  const json scene = json::parse(in);
  const json& mem = scene["mpm"]["membrane"];
  const json& gas = scene["mpm"]["bodies"][0];
  ASSERT_EQ(mem["shape"]["type"], "sphere");
  ASSERT_EQ(gas["material"]["type"], "ideal_gas");
  const double spacing = gas["spacing"];

  TempDir dir("mpm_balloon");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log =
      run_command(std::string(TETFSI_BINARY) + " run -q " + scene_file.string() + " --out " + out.string() + " 2>&1", &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv"), stats = read_csv(out / "stats.csv");
  const std::size_t last = probes.rows.size() - 1;
  ASSERT_NEAR(probes.at(last, "time"), scene["simulation"]["end_time"].get<double>(), 1e-9);

  // The discrete rest state: the faceted octant of the sphere encloses V_m0 (probe at t = 0), the
  // gas lattice holds N particles of volume spacing^3 at p0 (V_g0 = N spacing^3). Stretches are
  // taken from V_m0, and the gas is at p0 in V_g0: both limits below use these, not 4/3 pi R0^3.
  const double vm0 = probes.at(0, "volume"), vg0 = stats.at(0, "particles") * std::pow(spacing, 3);
  const Balloon b{mem["shape"]["radius"], mem["youngs_modulus"].get<double>() * mem["thickness"].get<double>(),
                  mem["poissons_ratio"], gas["pressure"], -mem.value("pressure", 0.0), gas["material"]["gamma"],
                  vg0 / vm0};
  const double l_ad = b.stretch(b.gamma), l_iso = b.stretch(1.0);
  Balloon b_log = b;
  b_log.log_strain = true;

  // Settled stretch: the mean over the last quarter of the run of (V / V_m0)^(1/3), and how far
  // it still moves in that window.
  double sum = 0, lo = 1e9, hi = -1e9;
  int n = 0;
  const double t_end = probes.at(last, "time");
  for (std::size_t r = 0; r <= last; ++r) {
    if (probes.at(r, "time") < 0.75 * t_end - 1e-12) continue;
    const double l = std::cbrt(probes.at(r, "volume") / vm0);
    sum += l, lo = std::min(lo, l), hi = std::max(hi, l), ++n;
  }
  ASSERT_GE(n, 3);
  const double l = sum / n;
  std::printf("[balloon ci] fill V_g0/V_m0 = %.4f; R/R0 settled %.4f (window %.4f..%.4f); adiabatic %.4f (%+.2f%%), "
              "isothermal %.4f (%+.2f%%); with log strain: adiabatic %.4f, isothermal %.4f\n",
              b.fill, l, lo, hi, l_ad, 100 * (l / l_ad - 1), l_iso, 100 * (l / l_iso - 1), b_log.stretch(b.gamma),
              b_log.stretch(1.0));
  // The scene separates the limits (by 4.3% in R: a linear membrane in vacuum needs more than 20%
  // stretch for 5%) and inflates noticeably (18-23%).
  EXPECT_GT(l_iso / l_ad, 1.04);
  EXPECT_GT(l_ad, 1.05);
  // Settled: the radius moves by less than 0.5% (a quarter of the band) over the window.
  EXPECT_LT(hi / lo - 1, 0.005);
  // Tolerance 2% in R (the acceptance band of the benchmark): the damped radius lies between the
  // adiabatic and isothermal roots up to 2% of the nearer one. The rest shapes are those of the
  // discretisation (fill ratio above), so what is left is the membrane's one-point quads on a
  // curved surface, the grid contact's standoff and gas that leaks through the membrane.
  EXPECT_GT(l, 0.98 * l_ad);
  EXPECT_LT(l, 1.02 * l_iso);

  // Energy. The gas ends between its isentrope at the settled volume, U0 (V_g0 / V)^(gamma - 1),
  // and its initial energy U0 (isothermal): viscous heating adds to it, nothing cools it; 1% below
  // the isentrope is allowed for the explicit scheme's own error (the balance below; measured
  // 0.3% above it: membrane damping and contact take most of the kinetic energy, not the gas).
  const double u0 = probes.at(0, "gas_internal"), u = probes.at(last, "gas_internal");
  const double u_isentrope = u0 * std::pow(vg0 / probes.at(last, "volume"), b.gamma - 1);
  // Balance (stored energy + damping and contact losses) against the energy at t = 0, all of it
  // the gas's internal energy: measured 1.2% lost in the first 0.1 s of the sudden expansion,
  // then within 0.2%.
  const std::size_t ns = stats.rows.size() - 1;
  double drift = 0;
  for (std::size_t r = 0; r <= ns; ++r) drift = std::max(drift, std::abs(stats.at(r, "energy_balance") / u0 - 1));
  std::printf("[balloon ci] gas energy %.4f: isentrope %.4f (%+.2f%%), U0 %.4f; balance drift %.2f%% of E0; contact "
              "loss %.4f, gas kinetic %.2e at the end\n",
              u, u_isentrope, 100 * (u / u_isentrope - 1), u0, 100 * drift, stats.at(ns, "contact_dissipation"),
              probes.at(last, "gas_kinetic"));
  EXPECT_GT(u, 0.99 * u_isentrope);
  EXPECT_LT(u, u0);
  EXPECT_LT(drift, 0.02);
  EXPECT_LT(probes.at(last, "gas_kinetic"), 1e-2 * u0);  // settled: 1e-3 of E0 measured
}
