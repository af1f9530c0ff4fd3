// The flagship scene end to end (data/scenes/smoke_sheets_ci.json, the CI-sized variant of the
// README's smoke_sheets.json): a smoke jet on two hanging rubber sheets, fluid and sheets coupled
// in one system per step, the fluid mesh following the sheets. Checks the output a user opens (one
// .pvd per object with a frame every 1/10 s, closed sheet surfaces as PLY, stats.csv, probes.csv)
// and that the jet pushes the deflector downstream.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "csv.hpp"
#include "ply_reader.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;

namespace {

/// "t points cells fields..." -> {points, cells}
std::pair<long, long> counts(const std::string& line) {
  std::istringstream ss(line);
  double t;
  long p, c;
  ss >> t >> p >> c;
  return {p, c};
}

}  // namespace

TEST(Flagship, SmokeSheetsRunsCoupledAndExportsEveryObject) {
  TempDir dir("flagship");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string msg = run_command(std::string(TETFSI_BINARY) + " run " + TETFSI_SOURCE_DIR +
                                          "/data/scenes/smoke_sheets_ci.json --out " + out.string() + " 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << msg;

  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 24u);  // 0.4 s at dt = 1/60 s
  for (std::size_t r = 0; r < stats.rows.size(); ++r) {
    EXPECT_LE(stats.at(r, "solver_residual"), 1e-8) << "step " << r + 1;
    EXPECT_GT(stats.at(r, "min_dihedral"), 1.0) << "step " << r + 1;
  }
  const auto fluid = lines(vtk_describe(out / "fluid.pvd", &status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(fluid.size(), 5u);  // t = 0, 0.1, ..., 0.4 s
  EXPECT_EQ(counts(fluid.back()).second, stats.at(stats.rows.size() - 1, "fluid_tets"));
  for (const char* sheet : {"deflector", "catcher"}) {
    const auto frames = lines(vtk_describe(out / (std::string(sheet) + ".pvd"), &status));
    ASSERT_EQ(status, 0);
    ASSERT_EQ(frames.size(), 5u) << sheet;
    // Each sheet's surface is closed and consistently oriented: every edge in exactly two
    // triangles, once each way.
    const auto ply = read_ply(out / "surfaces" / (std::string(sheet) + "_00004.ply"));
    ASSERT_GT(ply.triangles.size(), 50u);
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : ply.triangles)
      for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : edges) {
      EXPECT_EQ(n, 1) << sheet;
      EXPECT_EQ(edges.count({e.second, e.first}), 1u) << sheet;
    }
  }
  // The jet (+x) pushes the deflector's free edge downstream: seen +7.4 mm after 0.4 s (the
  // sheet swings about 6 cm in the full scene). Its hanging weight only moves it down (y).
  const Csv probes = read_csv(out / "probes.csv");
  const std::size_t last = probes.rows.size() - 1;
  EXPECT_GT(probes.at(last, "deflector_tip_x"), 2e-3);
  EXPECT_LT(probes.at(last, "deflector_tip_y"), 0.0);
  EXPECT_NE(read_text(out / "run.log").find("runner: coupled"), std::string::npos);
}

TEST(MeshCommand, TetrahedralizesAClosedSurfaceAndRejectsAnOpenOne) {
  TempDir dir("meshcmd");
  // A closed, outward 0.4 m cube as OBJ (1-based indices).
  std::ofstream(dir.path() / "cube.obj") << "v 0 0 0\nv 0.4 0 0\nv 0 0.4 0\nv 0.4 0.4 0\n"
                                            "v 0 0 0.4\nv 0.4 0 0.4\nv 0 0.4 0.4\nv 0.4 0.4 0.4\n"
                                            "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
                                            "f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
  int status = -1;
  const fs::path vtu = dir.path() / "cube.vtu";
  std::string msg = run_command(std::string(TETFSI_BINARY) + " mesh " + (dir.path() / "cube.obj").string() +
                                    " " + vtu.string() + " --edge-length 0.1 2>&1",
                                &status);
  ASSERT_EQ(status, 0) << msg;
  const std::string info = vtk_describe(vtu, &status);
  ASSERT_EQ(status, 0);
  long points = 0, cells = 0;
  std::istringstream(info) >> points >> cells;
  EXPECT_GT(cells, 20);
  EXPECT_NE(msg.find(std::to_string(cells) + " tets"), std::string::npos) << msg << "\n" << info;

  // The same cube without its top face is open: exit 2 and the message names the file.
  std::ofstream(dir.path() / "open.obj") << "v 0 0 0\nv 0.4 0 0\nv 0 0.4 0\nv 0.4 0.4 0\n"
                                            "v 0 0 0.4\nv 0.4 0 0.4\nv 0 0.4 0.4\nv 0.4 0.4 0.4\n"
                                            "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
                                            "f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
  msg = run_command(std::string(TETFSI_BINARY) + " mesh " + (dir.path() / "open.obj").string() + " " +
                        (dir.path() / "open.vtu").string() + " 2>&1",
                    &status);
  EXPECT_EQ(status, 2) << msg;
  EXPECT_NE(msg.find("open.obj"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir.path() / "open.vtu"));
}

TEST(Flagship, SameSceneGivesByteIdenticalOutput) {
  TempDir dir("flagship_det");
  // Two runs of 0.1 s (6 coupled steps, one with each thread count 2) write the same bytes.
  std::ifstream in(fs::path(TETFSI_SOURCE_DIR) / "data/scenes/smoke_sheets_ci.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  scene["simulation"]["end_time"] = 0.1;
  const fs::path file = dir.path() / "short.json";
  std::ofstream(file) << scene.dump(2);
  for (const char* name : {"a", "b"}) {
    int status = -1;
    const std::string msg = run_command(std::string(TETFSI_BINARY) + " run " + file.string() +
                                            " -q --threads 2 --out " + (dir.path() / name).string() + " 2>&1",
                                        &status);
    ASSERT_EQ(status, 0) << msg;
  }
  for (const char* file : {"fluid/fluid_00001.vtu", "deflector/deflector_00001.vtu", "surfaces/catcher_00001.ply",
                           "probes.csv"})
    EXPECT_EQ(read_text(dir.path() / "a" / file), read_text(dir.path() / "b" / file)) << file;
}
