// `tetfsi run` with boundary_conditions on a dynamic tet solid (solid runner): the beam of
// data/scenes/volume_mesh_beam.json (meshes/beam.vtu, ~1,100 tets, L = 1 m along x, nu = 0,
// E = 1e7 Pa, rho = 1000 kg/m^3), clamped at x = 0 (a `fixed` condition), no gravity, pulled along
// +x by a body force b = rho g (type body_force, N/m^3) and Rayleigh-damped (alpha = 100 1/s against the first axial
// mode omega = (pi / 2) sqrt(E / rho) = 157 rad/s) to rest: the settled end displacement is the
// hanging bar's rho g L^2 / (2E) = 0.4905 mm (uniaxial stress; strain <= 1e-3). Checked within 2 %
// (unstructured tets, consistent nodal loads; the St. Venant-Kirchhoff nonlinearity is 1.5e-3), the
// stats column load_potential = -f.d is reported, and the energy watchdog (which includes it) passes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

TEST(SolidLoadsRun, TetBarUnderBodyForceSettlesAtHangingBarDisplacement) {
  TempDir dir("body_force");
  const fs::path mesh = fs::path(TETFSI_SOURCE_DIR) / "data/scenes/meshes/beam.vtu";
  std::ofstream(dir.path() / "bar.json") << R"({
  "simulation": { "end_time": 0.5, "dt": 0.005, "frame_rate": 10, "gravity": [0, 0, 0] },
  "solids": [ {
    "name": "bar",
    "geometry": { "type": "volume_mesh", "file": ")" + mesh.string() + R"(" },
    "material": { "density": 1000, "youngs_modulus": 1e7, "poissons_ratio": 0.0, "rayleigh_alpha": 100 },
    "boundary_conditions": [
      { "type": "fixed", "box": { "lo": [-1, -1, -1], "hi": [1e-6, 1, 1] }, "components": "xyz" },
      { "type": "body_force", "box": { "lo": [-1, -1, -1], "hi": [2, 1, 1] }, "value": [9810, 0, 0] } ]
  } ],
  "probes": [ { "name": "end", "kind": "point_displacement", "solid": "bar", "point": [1.0, 0.0, 0.0] } ]
})";
  int status = -1;
  const std::string out = run_command(std::string(TETFSI_BINARY) + " run " + (dir.path() / "bar.json").string() +
                                          " --out " + (dir.path() / "out").string() + " --quiet 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << out;
  const Csv probes = read_csv(dir.path() / "out" / "probes.csv");
  const double exact = 1000 * 9.81 * 1.0 / (2 * 1e7);
  const double end = probes.at(probes.rows.size() - 1, "end_x");
  std::printf("tet bar under a body force: end %.6e m, rho g L^2 / (2E) = %.6e m (ratio %.5f)\n", end, exact,
              end / exact);
  EXPECT_NEAR(end, exact, 0.02 * exact);
  const Csv stats = read_csv(dir.path() / "out" / "stats.csv");
  EXPECT_LT(stats.at(stats.rows.size() - 1, "load_potential"), 0.0);  // -f.d: the load did positive work
}
