// A liquid column at the schema's largest viscosity (1e9 Pa s) in its first step (issue 44): the
// viscous step must see the flow gravity starts. Before, it acted on the advected velocity (zero in
// a first step) and its kinetic energy equalled the inviscid run's to every digit.
//
// Physics: a 0.3 m column of 1e9 Pa s liquid creeps at the Stokes velocity rho g L^2 / mu ~ 1e-6
// m/s (kinetic energy ~ 1e-11 J), i.e. it does not move; the viscous length of one step,
// sqrt(nu h) = 160 m, spans the column, so one implicit step removes the flow down to the
// discretization's floor. That floor is the velocity's variation across a tet that the node fits
// (fluid/README.md, "Velocity space") leave, O(h / L) of the velocity in a first-order scheme, so
// the kinetic energy is at most (h / L)^2 of the inviscid run's, at each resolution.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "csv.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using tetfsi::test::TempDir;

namespace {

constexpr double kColumnHeight = 0.3;  // L [m]

/// Kinetic energy [J] of a 0.2 x 0.3 x 0.3 m column of liquid of viscosity mu after one step of
/// 0.025 s on a mesh of edge h (fluid runner).
double first_step_kinetic_energy(const TempDir& dir, double mu, double h) {
  json s = json::parse(R"({
    "simulation": {"end_time": 0.025, "dt": 0.025, "frame_rate": 40},
    "domain": {"lo": [0, 0, 0], "hi": [0.6, 0.4, 0.3]},
    "fluid": {"type": "liquid", "fill": "regions", "regions": [{"type": "box", "lo": [0, 0, 0], "hi": [0.2, 0.3, 0.3]}]},
    "probes": [{"name": "ke", "kind": "fluid_kinetic_energy"}],
    "export": {"vtu": false}
  })");
  s["mesh"]["edge_length"] = h;
  s["fluid"]["viscosity"] = mu;
  const std::string name = "column_" + std::to_string(mu) + "_" + std::to_string(h);
  const fs::path file = dir.path() / (name + ".json"), out = dir.path() / name;
  std::ofstream(file) << s.dump();
  int status = -1;
  const std::string text = tetfsi::test::tetfsi_cmd("run " + file.string() + " --quiet --out " + out.string(), &status);
  EXPECT_EQ(status, 0) << text;
  const auto probes = tetfsi::test::read_csv(out / "probes.csv");
  return probes.rows.empty() ? -1 : probes.rows.back().back();
}

}  // namespace

TEST(ViscousColumn, AtTheLargestViscosityTheFirstStepBarelyMoves) {
  TempDir dir("viscous_column");
  for (const double h : {0.05, 0.025}) {
    const double inviscid = first_step_kinetic_energy(dir, 0.0, h);
    const double viscous = first_step_kinetic_energy(dir, 1e9, h);
    const double bound = (h / kColumnHeight) * (h / kColumnHeight);
    ASSERT_GT(inviscid, 0);
    EXPECT_GE(viscous, 0);
    EXPECT_LE(viscous, bound * inviscid) << "h = " << h << ": kinetic energy " << viscous << " J against "
                                         << inviscid << " J inviscid";
  }
}
