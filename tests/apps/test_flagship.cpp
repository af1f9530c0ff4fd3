// The flagship scene end to end (needs the CGAL mesher of mesh/): the fluid box with the ball is
// meshed as one complex, exported as fluid and solid .pvd objects (subdomain field) plus the
// ball's surface as PLY, and the counts VTK reads back match stats.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>

#include "csv.hpp"
#include "mesh/primitives.hpp"
#include "mesh/surface_checks.hpp"
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

TEST(Flagship, MeshesAndExportsTheScene) {
  TempDir dir("flagship");
  const fs::path out = dir.path() / "out";
  int status = -1;
  const std::string msg = run_command(std::string(TETFSI_BINARY) + " run " + TETFSI_SOURCE_DIR +
                                          "/data/scenes/flagship.json --out " + out.string() + " 2>&1",
                                      &status);
  ASSERT_EQ(status, 0) << msg;

  const Csv stats = read_csv(out / "stats.csv");
  ASSERT_EQ(stats.rows.size(), 1u);
  const auto fluid = lines(vtk_describe(out / "fluid.pvd", &status));
  ASSERT_EQ(status, 0);
  const auto ball = lines(vtk_describe(out / "ball.pvd", &status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(fluid.size(), 1u);
  ASSERT_EQ(ball.size(), 1u);
  EXPECT_EQ(counts(fluid[0]).second, stats.at(0, "fluid_tets"));
  EXPECT_EQ(counts(ball[0]).second, stats.at(0, "solid_tets"));
  EXPECT_NE(fluid[0].find("c:subdomain:1"), std::string::npos) << fluid[0];
  EXPECT_NE(ball[0].find("c:subdomain:1"), std::string::npos) << ball[0];
  EXPECT_GT(stats.at(0, "min_dihedral_deg"), 0.0);
  EXPECT_LT(stats.at(0, "max_dihedral_deg"), 180.0);

  // The ball's surface: closed (every edge in exactly two triangles, once each way), outward,
  // and enclosing the volume of the input icosphere up to the surface approximation error:
  // Mesh_3 keeps every facet within facet_distance d of the input (default: edge length near
  // solids / 10 = 0.004 m), so |V_mesh - V_input| <= area * d = 4 pi r^2 d.
  const auto ply = read_ply(out / "surfaces" / "ball_00000.ply");
  ASSERT_GT(ply.triangles.size(), 100u);
  std::map<std::pair<int, int>, int> edges;
  double volume = 0;
  for (const auto& t : ply.triangles) {
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
    volume += ply.positions[t[0]].dot(ply.positions[t[1]].cross(ply.positions[t[2]])) / 6;
  }
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  const double r = 0.2, d = 0.004;
  const double input = tetfsi::mesh::enclosed_volume(tetfsi::mesh::make_sphere(r, 3));
  EXPECT_NEAR(volume, input, 4 * M_PI * r * r * d);
  const double sphere = 4.0 / 3.0 * M_PI * r * r * r;
  const Csv probes = read_csv(out / "probes.csv");
  EXPECT_NEAR(probes.at(0, "ball_volume"), volume, 1e-6 * sphere) << "tet volume = surface volume";

  const std::string log = read_text(out / "run.log");
  EXPECT_NE(log.find("no physics model runs this scene yet"), std::string::npos);
  EXPECT_NE(log.find("mesh quality: "), std::string::npos);
  EXPECT_NE(log.find("interface triangles, each shared by one fluid and one solid tet: yes"), std::string::npos)
      << log;
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
  for (const char* name : {"a", "b"}) {
    int status = -1;
    const std::string msg = run_command(std::string(TETFSI_BINARY) + " run " + TETFSI_SOURCE_DIR +
                                            "/data/scenes/flagship.json -q --threads 2 --out " +
                                            (dir.path() / name).string() + " 2>&1",
                                        &status);
    ASSERT_EQ(status, 0) << msg;
  }
  for (const char* file : {"fluid/fluid_00000.vtu", "ball/ball_00000.vtu", "surfaces/ball_00000.ply"})
    EXPECT_EQ(read_text(dir.path() / "a" / file), read_text(dir.path() / "b" / file)) << file;
}
