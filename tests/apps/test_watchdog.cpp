// The physics watchdog (/simulation/watchdog, apps/run/watchdog.hpp) on the soft box of
// data/scenes/soft_drop.json pushed out of its range (issue 18): E = 1 Pa and g = 1e6 m/s^2
// invert tets, E = 1e13 Pa makes energy from nowhere, g = -1e7 (the schema's bound) too. Each run stops with
// exit 1 naming the solid, the step and the key to change, and no output file holds a non-finite
// number. The unchanged scene runs to its end.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "cli_helpers.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using tetfsi::test::committed;
using nlohmann::json;

namespace {

json soft_drop() { return committed("soft_drop.json"); }

struct RunResult {
  int status = -1;
  std::string out;
  fs::path dir;
};

RunResult run(const tetfsi::test::TempDir& tmp, const std::string& name, const json& scene) {
  RunResult r;
  const fs::path file = tmp.path() / (name + ".json");
  std::ofstream(file) << scene.dump();
  r.dir = tmp.path() / name;
  r.out = tetfsi::test::run_command("timeout -s KILL 300 " + std::string(TETFSI_BINARY) + " run " + file.string() +
                                        " --out " + r.dir.string() + " --quiet --threads 1 2>&1",
                                    &r.status);
  return r;
}

/// Every number in stats.csv, probes.csv and the PLY frames is finite.
void expect_all_finite(const fs::path& dir) {
  for (const char* csv : {"stats.csv", "probes.csv"}) {
    if (!fs::exists(dir / csv)) continue;
    const auto table = tetfsi::test::read_csv(dir / csv);
    for (const auto& row : table.rows) {
      EXPECT_EQ(row.size(), table.header.size()) << csv << ": a cell left empty (a non-finite value)";
      for (double v : row) EXPECT_TRUE(std::isfinite(v)) << csv;
    }
  }
  if (!fs::exists(dir / "surfaces")) return;
  for (const auto& e : fs::directory_iterator(dir / "surfaces")) {
    const auto ply = tetfsi::test::read_ply(e.path());
    for (const auto& p : ply.positions) EXPECT_TRUE(p.allFinite()) << e.path();
    for (const auto& v : ply.velocities) EXPECT_TRUE(v.allFinite()) << e.path();
  }
}

struct Case {
  std::string name;
  std::function<void(json&)> edit;
  std::vector<std::string> fragments;
};

/// Runs each case on `base` edited by it: exit 1, every fragment in the message, no non-finite number written.
void expect_stops(const tetfsi::test::TempDir& tmp, const json& base, const std::vector<Case>& cases) {
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    json s = base;
    c.edit(s);
    const RunResult r = run(tmp, c.name, s);
    EXPECT_EQ(r.status, 1) << r.out;
    for (const auto& f : c.fragments) EXPECT_NE(r.out.find(f), std::string::npos) << f << "\n" << r.out;
    expect_all_finite(r.dir);
  }
}

}  // namespace

TEST(Watchdog, UnphysicalSoftBoxRunsStopWithADiagnosis) {
  tetfsi::test::TempDir tmp("watchdog");
  const std::vector<Case> cases = {
      {"E_1Pa", [](json& s) { s["solids"][0]["material"]["youngs_modulus"] = 1.0; },
       {"solid 'jelly': ", "tets inverted", "/solids/0/material/youngs_modulus (now 1 Pa)", "allow_inverted"}},
      {"g_1e6", [](json& s) { s["simulation"]["gravity"] = {0, -1e6, 0}; },
       {"step 1 (t = 0.0333333 s): solid 'jelly': ", "tets inverted", "/simulation/gravity"}},
      {"E_1e13", [](json& s) { s["solids"][0]["material"]["youngs_modulus"] = 1e13; },
       {"solid 'jelly': the total energy", "energy from nowhere", "/simulation/dt", "max_energy_growth"}},
      {"g_1e7", [](json& s) { s["simulation"]["gravity"] = {0, -1e7, 0}; },  // the schema's bound
       {"step 1 (t = 0.0333333 s): ", "/simulation/gravity"}},
  };
  expect_stops(tmp, soft_drop(), cases);
}

TEST(Watchdog, AllowInvertedLetsTheRunContinueAndTheValidSceneRunsToItsEnd) {
  tetfsi::test::TempDir tmp("watchdog_ok");
  json s = soft_drop();
  s["simulation"]["end_time"] = 0.5;
  RunResult r = run(tmp, "valid", s);
  ASSERT_EQ(r.status, 0) << r.out;
  expect_all_finite(r.dir);

  s["solids"][0]["material"]["youngs_modulus"] = 1.0;
  s["simulation"]["watchdog"] = {{"allow_inverted", true}};
  r = run(tmp, "allowed", s);
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_GT(tetfsi::test::read_csv(r.dir / "stats.csv").rows.size(), 10u);
}

// The coupled runner watches the energy of a closed container (apps/run/coupled_runner.cpp): the
// block of data/scenes/floating_block_ci.json (half the water's density, its heave added mass
// above its mass) with the time-splitting baseline is the added-mass instability (the total
// energy oscillates with a growing amplitude), and the run stops with exit 1 on the energy rise,
// naming the step, the rise and the keys, before its step fails. The same scene with the
// simultaneous solve (Chentanez et al. 2006, eq. 7) runs to its end (its energy stays within 0.03 J of 113 J).
TEST(Watchdog, CoupledTimeSplittingWithALightBlockStopsOnTheEnergyRise) {
  tetfsi::test::TempDir tmp("watchdog_coupled");
  json s = committed("floating_block_ci.json");
  s["simulation"]["end_time"] = 0.5;
  s["coupling"]["scheme"] = "time_splitting";
  RunResult r = run(tmp, "splitting", s);
  EXPECT_EQ(r.status, 1) << r.out;
  for (const std::string f :
       {"fluid and solids (time_splitting coupling): the total energy", "J above its start", "energy from nowhere",
        "/simulation/dt", "/coupling/scheme \"simultaneous\"", "added-mass instability", "/solids/0/material",
        "/simulation/watchdog/max_energy_growth"})
    EXPECT_NE(r.out.find(f), std::string::npos) << f << "\n" << r.out;
  EXPECT_EQ(r.out.find("did not converge"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error: step "), std::string::npos) << r.out;
  expect_all_finite(r.dir);

  s["coupling"]["scheme"] = "simultaneous";
  r = run(tmp, "simultaneous", s);
  EXPECT_EQ(r.status, 0) << r.out;
  expect_all_finite(r.dir);
}

// A scene with an inflow supplies energy: its balance is not watched (run.log says why), so the
// energy rise of the jets does not stop it.
TEST(Watchdog, CoupledSceneWithAnInflowIsNotWatched) {
  tetfsi::test::TempDir tmp("watchdog_inflow");
  json s = committed("light_ball_in_water.json");
  s["domain"]["open_faces"] = {"x+"};
  s["domain"]["inflows"] = json::array({{{"lo", {-0.41, -0.1, -0.1}}, {"hi", {-0.39, 0.1, 0.1}}, {"velocity", {2, 0, 0}}}});
  const RunResult r = run(tmp, "inflow", s);
  EXPECT_EQ(r.status, 0) << r.out;
  std::ifstream log(r.dir / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("watchdog: the energy balance is not watched: /domain/inflows"), std::string::npos);
}

// The hex8 runner (apps/run/hex_runner.cpp) on data/scenes/hanging_block.json: E = 1 Pa under
// gravity inverts elements, and the diagnosis names the first (index, rest centre) and the keys;
// the sideways kick of kicked_sideways makes energy from nowhere. The kick with the chentanez
// scheme, a traction on the free end (a dead load whose work f.d the energy balance counts) and
// the unchanged block run through.
/// hanging_block kicked sideways at 2 m/s without gravity or floor, E = 1e7 Pa, with the
/// undamped trapezoidal rule at h = 1/30 s: its one linearised solve per step makes energy in the
/// large swing (46 J at the start, 746 J after 3 steps); the dissipative chentanez scheme is stable.
void kicked_sideways(json& s) {
  s["simulation"]["gravity"] = {0, 0, 0};
  s["simulation"]["dt"] = 1.0 / 30;
  s["obstacles"]["planes"] = json::array();
  s["solids"][0]["initial_velocity"] = {2, 0, 0};
  s["solids"][0]["material"]["youngs_modulus"] = 1e7;
  s["solids"][0]["integrator"] = {{"scheme", "trapezoidal"}};
}

TEST(Watchdog, HexBlockStopsOnAnInvertedElementOrAnEnergyRise) {
  tetfsi::test::TempDir tmp("watchdog_hex");
  const std::vector<Case> cases = {
      {"E_1Pa", [](json& s) { s["solids"][0]["material"]["youngs_modulus"] = 1.0; },
       {"hex solid 'block': ", "elements inverted", "the first element ", "rest centre (",
        "/solids/0/material/youngs_modulus (now 1 Pa)", "/simulation/dt"}},
      {"kick_E1e7", kicked_sideways,
       {"step 3 (t = 0.1 s): hex solid 'block': the total energy", "work of the loads", "energy from nowhere",
        "/simulation/dt", "/solids/0/integrator/scheme \"chentanez\"", "max_energy_growth"}},
  };
  json s = committed("hanging_block.json");
  s["simulation"]["end_time"] = 0.5;
  expect_stops(tmp, s, cases);
}

TEST(Watchdog, HexBlockWithATractionRunsThrough) {
  tetfsi::test::TempDir tmp("watchdog_hex_ok");
  json s = committed("hanging_block.json");
  s["simulation"]["end_time"] = 0.5;
  RunResult r = run(tmp, "valid", s);
  ASSERT_EQ(r.status, 0) << r.out;
  expect_all_finite(r.dir);
  json kicked = s;
  kicked_sideways(kicked);
  kicked["solids"][0]["integrator"]["scheme"] = "chentanez";
  kicked["simulation"]["end_time"] = 2.0;
  r = run(tmp, "kick_chentanez", kicked);
  EXPECT_EQ(r.status, 0) << r.out;
  expect_all_finite(r.dir);
  // Without gravity, a downward traction of 2 kPa (80 N) suddenly applied to the free (bottom) end:
  // the block oscillates about its stretched state and the load's work f.d reaches the peak
  // kinetic + strain energy, so a balance without that work would see a rise of about once its
  // scale (above max_energy_growth = 0.5).
  s["simulation"]["gravity"] = {0, 0, 0};
  s["obstacles"]["planes"] = json::array();
  s["solids"][0]["boundary_conditions"] = json::array(
      {{{"type", "traction"}, {"box", {{"lo", {-1, -0.001, -1}}, {"hi", {1, 0.001, 1}}}}, {"value", {0, -2000, 0}}}});
  r = run(tmp, "traction", s);
  ASSERT_EQ(r.status, 0) << r.out;
  expect_all_finite(r.dir);
  const auto stats = tetfsi::test::read_csv(r.dir / "stats.csv");
  EXPECT_LT(stats.at(stats.rows.size() - 1, "load_potential"), 0.0);  // the load did work f.d > 0
}

// g = -1e300 m/s^2 in every runner that has gravity: beyond the schema's bound of 1e7 m/s^2, each
// scene is refused (exit 2, naming the key) and no stats.csv or probes.csv is written, so no
// non-finite number (nor an empty cell standing for one) reaches them.
TEST(Watchdog, OverflowingGravityNeverReachesTheCsvFiles) {
  tetfsi::test::TempDir tmp("watchdog_1e300");
  struct Scene {
    std::string file;
    std::function<void(json&)> edit;
  };
  const std::vector<Scene> scenes = {
      {"light_ball_in_water.json", [](json&) {}},  // coupled
      {"hanging_block.json", [](json&) {}},                                        // hex
      {"dam_break_ci.json", [](json& s) { s["solids"] = json::array(); s["probes"].erase(3); }},  // fluid
      {"floating_block_ci.json", [](json&) {}},                                    // coupled, free surface
  };
  for (const auto& c : scenes) {
    SCOPED_TRACE(c.file);
    json s = committed(c.file);
    c.edit(s);
    s["simulation"]["gravity"] = {0, -1e300, 0};
    s["simulation"]["end_time"] = 0.05;
    const RunResult r = run(tmp, c.file.substr(0, c.file.size() - 5), s);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_NE(r.out.find("/simulation/gravity"), std::string::npos) << r.out;
    expect_all_finite(r.dir);
  }
}
