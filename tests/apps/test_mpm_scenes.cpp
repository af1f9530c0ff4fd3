// The committed airbag and trampoline scenes (data/scenes/airbag_ci.json, trampoline_ci.json)
// through `tetfsi run`: free flight before contact is exact, the energy balance (stored energy +
// contact losses - external work - energy brought in by the gas source) stays at its start value,
// the source adds the mass it was asked for, and the bodies do what the scene is about (the
// cushion inflates and throws the impactor back; the sheet catches the drop and recoils).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

std::string run_tetfsi(const std::string& args, int* status) {
  return run_command(std::string(TETFSI_BINARY) + " " + args + " 2>&1", status);
}

const fs::path kScenes = fs::path(TETFSI_SOURCE_DIR) / "data" / "scenes";

/// Largest |energy_balance - its first value| over the stats rows, and that first value.
double balance_drift(const Csv& stats, double* b0) {
  *b0 = stats.at(0, "energy_balance");
  double worst = 0;
  for (std::size_t r = 0; r < stats.rows.size(); ++r) worst = std::max(worst, std::abs(stats.at(r, "energy_balance") - *b0));
  return worst;
}

}  // namespace

TEST(MpmScenes, AirbagCiInflatesAndThrowsTheImpactorBack) {
  TempDir dir("mpm_airbag");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_tetfsi("run -q " + (kScenes / "airbag_ci.json").string() + " --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv"), stats = read_csv(out / "stats.csv");
  const std::size_t last = probes.rows.size() - 1, n = stats.rows.size() - 1;
  ASSERT_NEAR(probes.at(last, "time"), 1.6, 1e-12);

  // Source: mass rate 0.05 for 0.6 time units in particles of density 1 x 0.05^3 = 1.25e-4: 240
  // particles (one fewer if the last is due only after round-off), each bringing E m / rho0 =
  // 25 x 1.25e-4 of internal energy at rest.
  const double added = stats.at(n, "particles") - (228 + 52);  // gas + impactor lattices at t = 0
  EXPECT_GE(added, 239);
  EXPECT_LE(added, 240);
  EXPECT_NEAR(stats.at(n, "injected_energy"), added * 1.25e-4 * 25.0, 1e-12);

  // Energy: stored + losses - injected stays at its start value (measured drift 3e-5 of the energy
  // put in).
  double b0 = 0;
  const double drift = balance_drift(stats, &b0);
  const double supplied = probes.at(0, "energy") + stats.at(n, "injected_energy");
  std::printf("[airbag ci] %.0f particles added, balance drift %.2e of %.4f supplied; top of cushion %.3f -> %.3f; "
              "impactor kinetic %.5f -> %.5f\n",
              added, drift / supplied, supplied, probes.at(0, "top_y"), probes.at(last, "top_y"),
              probes.at(0, "impactor_kinetic"), probes.at(last, "impactor_kinetic"));
  EXPECT_LT(drift, 1e-4 * supplied);

  // Free flight of the impactor at 0.4 until it reaches the inflated cushion (after t = 0.75).
  double lowest = 1e9;
  for (std::size_t r = 0; r <= last; ++r) {
    const double t = probes.at(r, "time");
    if (t <= 0.75 + 1e-12) {
      EXPECT_NEAR(probes.at(r, "impactor_y"), probes.at(0, "impactor_y") - 0.4 * t, 1e-9) << t;
    }
    lowest = std::min(lowest, probes.at(r, "impactor_y"));
  }
  // The cushion inflated (its top rose from 0.2 by more than its half height) before the strike.
  EXPECT_GT(probes.at(3, "top_y"), 0.5);  // t = 0.75
  // The impactor was stopped well above the cushion's lower panel (y = -0.2; impactor radius 0.2)
  // and moves up again at the end.
  EXPECT_GT(lowest - 0.2, 0.0);
  EXPECT_GT(probes.at(last, "impactor_y"), lowest + 0.1);
  EXPECT_GT(stats.at(n, "contact_dissipation"), 0.0);
}

TEST(MpmScenes, TrampolineCiCatchesTheDropAndRecoils) {
  TempDir dir("mpm_trampoline");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string log = run_tetfsi("run -q " + (kScenes / "trampoline_ci.json").string() + " --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv"), stats = read_csv(out / "stats.csv");
  const std::size_t last = probes.rows.size() - 1;
  ASSERT_NEAR(probes.at(last, "time"), 6e-3, 1e-15);

  // Free fall (v0 = -2 m/s, g = 9.81) until the drop comes within distance_factor x cell = 0.5 mm
  // of the sheet (the gap is 1 mm at t = 0): the first row, t = 0.2 ms.
  const double t1 = probes.at(1, "time");
  EXPECT_NEAR(probes.at(1, "drop_top_z"), probes.at(0, "drop_top_z") - 2.0 * t1 - 0.5 * 9.81 * t1 * t1, 1e-8);

  double b0 = 0;
  const double drift = balance_drift(stats, &b0);
  double lowest = 0, worst_overlap = -1;
  for (std::size_t r = 0; r <= last; ++r) {
    lowest = std::min(lowest, probes.at(r, "center_z"));
    // The drop's bottom particle stays above the sheet's centre (within half a cell, the contact's reach).
    worst_overlap = std::max(worst_overlap, probes.at(r, "center_z") - probes.at(r, "drop_bottom_z"));
  }
  std::printf("[trampoline ci] balance drift %.2e of E0 = %.4g J; centre down to %.3f mm, %.3f mm at the end; "
              "largest overlap of the drop's bottom below the centre %.3f mm\n",
              drift / b0, b0, lowest * 1e3, probes.at(last, "center_z") * 1e3, worst_overlap * 1e3);
  EXPECT_LT(drift, 5e-3 * b0);  // measured 2.6e-3
  EXPECT_LT(lowest, -2e-3);     // the sheet is pushed down by millimetres
  EXPECT_GT(probes.at(last, "center_z"), lowest + 0.1e-3);  // and recoils
  EXPECT_LT(worst_overlap, 1e-3);
  EXPECT_GT(stats.at(stats.rows.size() - 1, "contact_dissipation"), 0.0);
}

TEST(MpmScenes, SurfaceFilesGiveAParticleBodyAndAQuadMembrane) {
  // A closed cube OBJ (12 outward triangles) read twice with assimp: as a particle body (the
  // lattice sites inside it: 8^3 at spacing 0.05 in [0.2, 0.6]^3) and, scaled by 1.5 about the
  // origin and moved, as a closed membrane (each triangle three quads: 36) whose enclosed volume
  // is that of the cube, 0.6^3; at rest without gravity nothing moves.
  TempDir dir("mpm_files");
  std::ofstream(dir.path() / "cube.obj") << "v 0.2 0.2 0.2\nv 0.6 0.2 0.2\nv 0.6 0.6 0.2\nv 0.2 0.6 0.2\n"
                                            "v 0.2 0.2 0.6\nv 0.6 0.2 0.6\nv 0.6 0.6 0.6\nv 0.2 0.6 0.6\n"
                                            "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                            "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  const fs::path scene = dir.path() / "files.json", out = dir.path() / "out";
  std::ofstream(scene) << R"({"simulation": {"end_time": 1e-3, "frame_rate": 2000, "gravity": [0, 0, 0]},
    "mpm": {"grid": {"lo": [0, 0, 0], "hi": [1, 1, 1], "cell": 0.1},
            "bodies": [{"name": "block", "shape": {"type": "file", "file": "cube.obj"}, "spacing": 0.05,
                        "material": {"type": "linear_elastic", "density": 1000, "youngs_modulus": 1e6, "poissons_ratio": 0.3}}],
            "membrane": {"shape": {"type": "file", "file": "cube.obj", "unit_scale": 1.5, "translation": [-0.1, -0.1, -0.1]},
                         "element_size": 0.1, "thickness": 1e-3, "density": 1000, "youngs_modulus": 1e6, "poissons_ratio": 0.3}},
    "probes": [{"name": "volume", "kind": "membrane_volume"},
               {"name": "block_energy", "kind": "body_energy", "body": "block"}]})";
  int status = -1;
  const std::string log = run_tetfsi("run -q " + scene.string() + " --out " + out.string(), &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(out / "probes.csv"), stats = read_csv(out / "stats.csv");
  EXPECT_EQ(stats.at(0, "particles"), 512);
  EXPECT_EQ(stats.at(0, "membrane_elements"), 36);
  const std::size_t last = probes.rows.size() - 1;
  // assimp keeps vertices in single precision: 0.2 becomes 0.2 + 3e-9 (measured 1.6e-7 relative).
  EXPECT_NEAR(probes.at(0, "volume") / (0.6 * 0.6 * 0.6), 1.0, 1e-6);
  EXPECT_EQ(probes.at(last, "volume"), probes.at(0, "volume"));
  EXPECT_EQ(probes.at(last, "block_energy"), 0.0);
}
