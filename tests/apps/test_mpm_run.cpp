// The mpm runner through the built tetfsi binary: the committed CI gas-expansion scene (Lian, Liu
// & Zhang 2014, section 7.3) settles to the paper's radius and energy loss; its frames read back
// with VTK; every committed mpm scene validates; coarse variants of the sphere scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace tetfsi::test;

namespace {

std::string run_tetfsi(const std::string& args, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

const fs::path kScenes = fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes";

/// The committed scene data/scenes/<name>.json with `patch` applied, written to `file`.
void write_variant(const std::string& name, const fs::path& file, const std::function<void(json&)>& patch) {
  std::ifstream in(kScenes / (name + ".json"));
  json scene = json::parse(in);
  patch(scene);
  std::ofstream(file) << scene.dump(2);
}

}  // namespace

TEST(MpmRun, GasExpansionCiSettlesToPaperRadiusAndEnergyLoss) {
  TempDir dir("mpm_run");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_tetfsi("run -q " + (kScenes / "gas_expansion_ci.json").string() + " --out " + out.string(),
                                 &status);
  ASSERT_EQ(status, 0) << log;

  // Fig. 16: both tracked radii end within 2% of the paper's 0.96.
  const Csv probes = read_csv(out / "probes.csv");
  ASSERT_GT(probes.rows.size(), 2u);
  const std::size_t last = probes.rows.size() - 1;
  const double t_end = 4.0;  // the window of the paper-resolution scene (data/scenes/gas_expansion.json)
  EXPECT_NEAR(probes.at(last, "time"), t_end, 1e-9);
  EXPECT_NEAR(probes.at(0, "r_0deg"), 0.5, 1e-12);   // initial membrane: x = 0.5, y = 1
  EXPECT_NEAR(probes.at(0, "r_90deg"), 1.0, 1e-12);
  std::printf("[gas ci] r_0deg=%.4f r_90deg=%.4f\n", probes.at(last, "r_0deg"), probes.at(last, "r_90deg"));
  EXPECT_NEAR(probes.at(last, "r_0deg") / 0.96, 1.0, 0.02);
  EXPECT_NEAR(probes.at(last, "r_90deg") / 0.96, 1.0, 0.02);

  // Settled time t_s: the first frame from which neither radius moves by more than 0.5% (a
  // quarter of the 2% radius band) in any later frame. The paper reports the state once the
  // membrane "is damped to a steady state" (section 7.3); at least one time unit of it is kept.
  std::size_t settled = last;
  for (std::size_t r = last + 1; r-- > 0;) {
    bool still = true;
    for (std::size_t k = r; k <= last && still; ++k)
      for (const char* name : {"r_0deg", "r_90deg"})
        still = still && std::abs(probes.at(k, name) / probes.at(r, name) - 1) < 0.005;
    if (!still) break;
    settled = r;
  }
  const double t_s = probes.at(settled, "time");
  ASSERT_LE(t_s, t_end - 1.0) << "the membrane has not settled a time unit before the end";

  // Fig. 18: 3-7% of the initial energy E0 V0 = 25 x (0.45 x 0.95 x 0.1) (Table 2, quarter model)
  // is lost once settled; the stats column agrees with the stored energy it is made of. One stats
  // row per frame (stats_rows_per_frame 1, rows at 0.25, 0.5, ...; probes also have t = 0), each
  // covering thousands of coupled steps.
  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 16u);  // frames at 0.25, 0.5, ..., 4.0
  const std::size_t n = stats.rows.size() - 1;
  const double e0 = 25.0 * 0.45 * 0.95 * 0.1;
  double substeps = 0, worst_balance = 0;
  for (std::size_t r = 0; r <= n; ++r) {
    EXPECT_NEAR(stats.at(r, "time"), 0.25 * double(r + 1), 1e-9);
    EXPECT_NEAR(stats.at(r, "energy_loss_fraction"), 1 - stats.at(r, "stored_energy") / e0, 1e-9);
    substeps += stats.at(r, "substeps");
    // Stored energy + contact dissipation (work of the contact forces on the particles and the FE
    // nodes) stays at E0: what the contact removes is booked, nothing else is lost.
    worst_balance = std::max(worst_balance, std::abs(stats.at(r, "energy_balance") / e0 - 1));
  }
  ASSERT_GE(settled, 1u);
  const std::size_t rs = settled - 1;  // stats row of t_s
  ASSERT_NEAR(stats.at(rs, "time"), t_s, 1e-9);
  const double loss_settled = stats.at(rs, "energy_loss_fraction"), loss_end = stats.at(n, "energy_loss_fraction");
  // The loss keeps growing after settling (sustained contact removes a little relative velocity
  // every step; first order in dt, see coupling/mpm/README.md). Bound on its rate: the paper gives
  // one figure for the settled loss (about 5%, accepted 3-7%), so a drift is tolerable only if over
  // the rest of the window it cannot move the loss by more than the band's half width (2 points):
  // rate < 0.02 / (t_end - t_s). This follows from the acceptance band, not from the measured rate.
  const double rate = (loss_end - loss_settled) / (t_end - t_s), rate_bound = 0.02 / (t_end - t_s);
  std::printf("[gas ci] %.0f coupled steps in %zu rows; settled at t = %.2f with %.2f%% lost; %.2f%% at t = %.1f: "
              "%.2f%% per time unit (bound %.2f%%); worst |balance / E0 - 1| %.2e\n",
              substeps, n + 1, t_s, 100 * loss_settled, 100 * loss_end, t_end, 100 * rate, 100 * rate_bound,
              worst_balance);
  EXPECT_GT(substeps, 1000 * (n + 1));
  EXPECT_LT(worst_balance, 5e-3);
  EXPECT_GT(stats.at(n, "contact_dissipation") / e0, 0.03);  // the loss is the contact's
  EXPECT_GT(loss_settled, 0.03);
  EXPECT_LT(loss_settled, 0.07);
  EXPECT_GE(rate, 0.0);
  EXPECT_LT(rate, rate_bound);
  const double particles = 9 * 19 * 2;  // lattice of spacing 0.05 in the 0.45 x 0.95 x 0.1 block
  EXPECT_EQ(stats.at(n, "particles"), particles);
  EXPECT_EQ(stats.at(n, "membrane_elements"), 15);  // 10 + 5 elements of size 0.1 along the quarter

  // Frames every 0.25 (frame_rate 4): VTK reads the particle point cloud and the membrane quads.
  const auto frames = lines(vtk_describe(out / "particles.pvd", &status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(frames.size(), 17u);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::istringstream ss(frames[k]);
    double t;
    std::string rest;
    ss >> t;
    std::getline(ss, rest);
    EXPECT_NEAR(t, 0.25 * k, 1e-9);
    EXPECT_EQ(rest, " 342 342 p:velocity:3 p:pressure:1 p:density:1 p:internal_energy:1") << "frame " << k;
  }
  const auto membrane = lines(vtk_describe(out / "membrane.pvd", &status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(membrane.size(), 17u);
  EXPECT_NE(membrane.back().find(" 32 15 p:velocity:3 c:stress:9"), std::string::npos) << membrane.back();
  const auto ply = read_ply(out / "surfaces" / "membrane_00016.ply");
  EXPECT_EQ(ply.positions.size(), 32u);
  EXPECT_EQ(ply.triangles.size(), 30u);
  // The last PLY frame is the final state: node 0 is the membrane node on y = 0 (radius at 0 deg).
  EXPECT_NEAR(ply.positions[0].x(), probes.at(last, "r_0deg"), 1e-6);
}

TEST(MpmRun, CommittedMpmScenesValidate) {
  int found = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    const json scene = json::parse(in);
    if (!scene.contains("mpm")) continue;
    ++found;
    int status = -1;
    const std::string msg = run_tetfsi("validate " + entry.path().string(), &status);
    EXPECT_EQ(status, 0) << entry.path() << ": " << msg;
  }
  EXPECT_GE(found, 9);  // the four paper examples, gas_expansion_ci, airbag(_ci), trampoline(_ci)
}

TEST(MpmRun, WaterSphereFliesFreelyUntilContact) {
  // Section 7.2 at a coarse grid (cell 2 mm, spacing 1 mm), run for 25 us: the sphere starts
  // 0.5 mm above the membrane at 10 m/s and contact is confirmed within distance_factor x cell =
  // 0.2 mm, so there is no contact before 30 us. Unstressed water in uniform
  // motion stays so: the sphere top moves by exactly -10 m/s x t, the membrane centre stays at 0
  // and the kinetic energy 1/2 m v^2 is unchanged.
  TempDir dir("mpm_water");
  const fs::path scene = dir.path() / "water.json", out = dir.path() / "out";
  // The grid of the 1 mm scene at cell 2 mm, its lower corner moved down by half a spacing so that
  // the lattice (spacing 1 mm from the sphere's box corner) sits at in-cell positions.
  write_variant("water_sphere", scene, [](json& s) {
    s["simulation"]["end_time"] = 2.5e-5;
    s["simulation"]["frame_rate"] = 1e5;
    s["mpm"]["grid"] = {{"lo", {-29.5e-3, -29.5e-3, -25.5e-3}}, {"hi", {29e-3, 29e-3, 17.5e-3}}, {"cell", 2e-3}};
    s["mpm"]["bodies"][0]["spacing"] = 1e-3;
    s["mpm"]["membrane"]["element_size"] = 2e-3;
    s["mpm"]["contact"] = {{"distance_factor", 0.1}};
    s["mpm"]["stats_rows_per_frame"] = 5;
    s["probes"] = {{{"name", "c"}, {"kind", "membrane_point"}, {"point", {0, 0, 0}}, {"quantity", "z"}},
                   {{"name", "top"}, {"kind", "particle_point"}, {"body", "water"}, {"point", {0, 0, 9.5e-3}}, {"quantity", "z"}},
                   {{"name", "e"}, {"kind", "total_energy"}}};
  });
  int status = -1;
  const std::string log = run_tetfsi("run -q " + scene.string() + " --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv");
  const std::size_t n = probes.rows.size() - 1;
  ASSERT_GT(n, 10u);
  EXPECT_NEAR(probes.at(n, "time"), 2.5e-5, 1e-15);
  EXPECT_NEAR(probes.at(0, "top"), 9.5e-3, 0.5e-3);  // nearest particle to the top (0, 0, 9.5) mm
  EXPECT_NEAR(probes.at(n, "top") - probes.at(0, "top"), -10 * 2.5e-5, 1e-3 * 10 * 2.5e-5);
  EXPECT_EQ(probes.at(n, "c"), 0.0);
  EXPECT_NEAR(probes.at(n, "e"), probes.at(0, "e"), 1e-6 * probes.at(0, "e"));
  const Csv stats = read_csv(out / "stats.csv");
  EXPECT_EQ(stats.at(stats.rows.size() - 1, "contact_nodes"), 0);
  EXPECT_GT(stats.at(0, "particles"), 300);  // (4/3) pi 4.5^3 mm^3 / 1 mm^3 = 382 lattice sites
  EXPECT_LT(stats.at(0, "particles"), 460);
  EXPECT_EQ(stats.at(0, "membrane_elements"), 25 * 25);
}

TEST(MpmRun, CoarseSphereOnMembraneBouncesWithoutGainingEnergy) {
  // Section 7.1 (sphere on membrane) at cell 2 mm and particle spacing 1 mm, 0.4 ms, a row every
  // 5 us (57 coupled steps each). This run used to blow up: in free flight, because every other
  // particle layer sat on a node plane (MpmSolver now closes such stencils, and the example puts
  // the lattice at in-cell positions), and at 0.3 ms in contact, because the runner landed each
  // row with two shorter steps and the membrane took dt^{n+1/2} for dt^n (eq. 46). Now the sphere
  // presses the membrane down and rebounds, the contact only removes energy, and the energy
  // balance (stored + contact losses) stays at its start value. (The runner now takes equal steps
  // within a row, so this run no longer exercises varying steps: the membrane and MPM unit tests
  // with step patterns do. It fails without close_stencil: drift 7.6e-3 E0.) The scene is
  // data/scenes/sphere_on_membrane.json at cell 2 mm, its grid corner moved by half a spacing in x
  // and y so that the 1 mm lattice sits at in-cell positions (as the former compiled example did).
  TempDir dir("mpm_coarse_sphere");
  const fs::path scene = dir.path() / "sphere.json", out = dir.path() / "out";
  write_variant("sphere_on_membrane", scene, [](json& s) {
    s["simulation"]["frame_rate"] = 2e5;
    s["mpm"]["grid"] = {{"lo", {-29.5e-3, -29.5e-3, -25e-3}}, {"hi", {29e-3, 29e-3, 18e-3}}, {"cell", 2e-3}};
    s["mpm"]["bodies"][0]["spacing"] = 1e-3;
    s["mpm"]["membrane"]["element_size"] = 2e-3;
  });
  int status = -1;
  const std::string log = run_tetfsi("run -q " + scene.string() + " --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const Csv stats = read_csv(out / "stats.csv"), probes = read_csv(out / "probes.csv");
  const std::size_t n = stats.rows.size() - 1;  // rows at 5, 10, ..., 400 us
  ASSERT_EQ(n, 79u);
  ASSERT_EQ(probes.rows.size(), n + 2);  // and t = 0
  EXPECT_NEAR(stats.at(n, "time"), 4e-4, 1e-15);
  // Stored energy at t = 0 (no losses yet, so also the balance then): 1/2 m (10 m/s)^2.
  const double e0 = stats.at(0, "stored_energy") / (1 - stats.at(0, "energy_loss_fraction")), b0 = e0;
  double worst_balance = 0, most_stored = 0, lowest_centre = 0, lowest_top = 1;
  for (std::size_t r = 0; r <= n; ++r) {
    worst_balance = std::max(worst_balance, std::abs(stats.at(r, "energy_balance") - b0));
    most_stored = std::max(most_stored, stats.at(r, "stored_energy"));
    lowest_centre = std::min(lowest_centre, probes.at(r + 1, "center_z"));
    lowest_top = std::min(lowest_top, probes.at(r + 1, "sphere_top_z"));
  }
  std::printf("[coarse sphere on membrane] |balance drift| <= %.2e E0, max stored %.6f E0, centre down to %.3f mm, "
              "top from %.3f to %.3f to %.3f mm\n",
              worst_balance / e0, most_stored / e0, lowest_centre * 1e3, probes.at(0, "sphere_top_z") * 1e3, lowest_top * 1e3,
              probes.at(n + 1, "sphere_top_z") * 1e3);
  // Energy: the balance within 0.2% of E0 (measured 8.8e-4); the stored energy never above its start.
  EXPECT_LT(worst_balance, 2e-3 * e0);
  EXPECT_LE(most_stored, e0 * (1 + 1e-6));
  // Contact happened (the membrane is pushed down by about a millimetre) and the sphere rebounds.
  EXPECT_LT(lowest_centre, -0.5e-3);
  EXPECT_GT(probes.at(n + 1, "sphere_top_z") - lowest_top, 0.5e-3);
}
