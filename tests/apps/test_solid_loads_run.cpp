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

namespace {
/// `tetfsi run` on dir/name.json into dir/out; returns probes.csv (fails the test on a non-zero exit).
Csv run_in(const fs::path& dir, const std::string& name) {
  int status = -1;
  const std::string out = run_command(std::string(TETFSI_BINARY) + " run " + (dir / (name + ".json")).string() +
                                          " --out " + (dir / "out").string() + " --quiet 2>&1",
                                      &status);
  EXPECT_EQ(status, 0) << out;
  return read_csv(dir / "out" / "probes.csv");
}
}  // namespace

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
  const Csv probes = run_in(dir.path(), "bar");
  ASSERT_FALSE(probes.rows.empty());
  const double exact = 1000 * 9.81 * 1.0 / (2 * 1e7);
  const double end = probes.at(probes.rows.size() - 1, "end_x");
  std::printf("tet bar under a body force: end %.6e m, rho g L^2 / (2E) = %.6e m (ratio %.5f)\n", end, exact,
              end / exact);
  EXPECT_NEAR(end, exact, 0.02 * exact);
  const Csv stats = read_csv(dir.path() / "out" / "stats.csv");
  EXPECT_LT(stats.at(stats.rows.size() - 1, "load_potential"), 0.0);  // -f.d: the load did positive work
}

// A hex8 unit cube (2 x 2 x 2 cells, StVK, E = 1e6 Pa, nu = 0.3) with symmetry planes x = y = z = 0
// (`fixed` on one component each) and a follower `pressure` p = 1e5 Pa on its other faces, static in
// 4 load steps through the hex runner: homogeneous x = lambda X with Cauchy stress -p I, i.e.
// 3 K lambda^2 + 2 p lambda - 3 K = 0 (K = lambda_L + 2 mu / 3; tests/solid/test_loads.cpp). The corner
// (1, 1, 1) moves by lambda - 1 along each axis, to 1e-9, and every probes.csv row (time = load
// factor) holds the exact stretch of its pressure.
TEST(SolidLoadsRun, HexCubeUnderFollowerPressureMatchesExactStretch) {
  TempDir dir("hex_pressure");
  std::ofstream(dir.path() / "cube.json") << R"({
  "simulation": { "end_time": 1.0 },
  "solids": [ {
    "name": "cube",
    "geometry": { "type": "box", "size": [1, 1, 1] },
    "placement": { "translation": [0.5, 0.5, 0.5] },
    "model": { "type": "hex8", "nx": 2, "ny": 2, "nz": 2, "analysis": "static" },
    "material": { "density": 1000, "youngs_modulus": 1e6, "poissons_ratio": 0.3 },
    "boundary_conditions": [
      { "type": "fixed", "box": { "lo": [-1, -1, -1], "hi": [0, 2, 2] }, "components": "x" },
      { "type": "fixed", "box": { "lo": [-1, -1, -1], "hi": [2, 0, 2] }, "components": "y" },
      { "type": "fixed", "box": { "lo": [-1, -1, -1], "hi": [2, 2, 0] }, "components": "z" },
      { "type": "pressure", "box": { "lo": [1, -1, -1], "hi": [2, 2, 2] }, "pressure": 1e5 },
      { "type": "pressure", "box": { "lo": [-1, 1, -1], "hi": [2, 2, 2] }, "pressure": 1e5 },
      { "type": "pressure", "box": { "lo": [-1, -1, 1], "hi": [2, 2, 2] }, "pressure": 1e5 } ],
    "static": { "load_steps": 4 }
  } ],
  "probes": [ { "name": "corner", "kind": "point_displacement", "solid": "cube", "point": [1, 1, 1] } ]
})";
  const Csv probes = run_in(dir.path(), "cube");
  ASSERT_EQ(probes.rows.size(), 5u);
  const double E = 1e6, nu = 0.3, lame = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double bulk = lame + 2 * mu / 3;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    const double p = 1e5 * probes.at(r, "time");
    const double stretch = (std::sqrt(p * p + 9 * bulk * bulk) - p) / (3 * bulk);
    for (const char* c : {"corner_x", "corner_y", "corner_z"}) EXPECT_NEAR(probes.at(r, c), stretch - 1, 1e-9) << r;
  }
}
