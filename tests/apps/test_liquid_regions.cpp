// Liquid regions against the container's walls, through `tetfsi run` (fluid/README.md, "Liquids"):
//  - a box region whose faces lie exactly on five walls of the domain (a layer filling the bottom
//    of the tank) is still water: its kinetic energy stays at round-off and it keeps the box's
//    volume. Before, the nodes on those walls read phi = 0, counted as air with p = 0, and the
//    whole layer fell freely in the first step (kinetic energy 1/2 rho V (g h)^2);
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

TEST(LiquidRegions, ABoxOnTheWallsIsStillWater) {
  const double rho = 1000, g = 9.81, depth = 0.3, volume = 0.6 * 0.3 * 0.3;
  json scene = json::parse(R"({
    "simulation": {"end_time": 0.2, "dt": 0.02, "frame_rate": 50},
    "domain": {"lo": [0, 0, 0], "hi": [0.6, 0.6, 0.3]},
    "mesh": {"edge_length": 0.06},
    "fluid": {"type": "liquid", "viscosity": 0, "fill": "regions", "solver": {"tolerance": 1e-10},
              "regions": [{"type": "box", "lo": [0, 0, 0], "hi": [0.6, 0.3, 0.3]}]},
    "probes": [{"name": "liquid_volume", "kind": "fluid_volume"},
               {"name": "kinetic_energy", "kind": "fluid_kinetic_energy"}],
    "export": {"vtu": false, "surfaces": "none"}
  })");
  TempDir dir("liquid_box_on_walls");
  std::ofstream(dir.path() / "scene.json") << scene.dump(2);
  int status = -1;
  const std::string log = tetfsi_cmd("run " + (dir.path() / "scene.json").string() + " --out " +
                                         (dir.path() / "out").string() + " --quiet --threads 1",
                                     &status);
  ASSERT_EQ(status, 0) << log;
  const Csv probes = read_csv(dir.path() / "out" / "probes.csv");
  ASSERT_EQ(probes.rows.size(), 11u);  // t = 0 and ten steps
  // The potential energy scale rho g V H is 159 J; free fall would give 1/2 rho V (g h)^2 = 1.0 J
  // after the first step.
  double worst_ke = 0;
  for (std::size_t r = 0; r < probes.rows.size(); ++r) {
    worst_ke = std::max(worst_ke, probes.at(r, "kinetic_energy"));
    EXPECT_NEAR(probes.at(r, "liquid_volume"), volume, 1e-9 * volume) << "row " << r;
  }
  EXPECT_LE(worst_ke, 1e-12 * rho * g * volume * depth);
  std::printf("box region on five walls: largest kinetic energy %.3e J over 10 steps\n", worst_ke);
}
