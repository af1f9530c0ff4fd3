// Volume meshes read from files (mesh/volume_mesh.hpp): a CGAL tet mesh of a box written as
// .vtu (inline binary, ASCII, raw appended) and .msh (4.1, 2.2) reads back node for node and
// tet for tet, and the checks refuse or repair the defects they list.
#include <gtest/gtest.h>

#include <fstream>

#include "mesh/complex_mesher.hpp"
#include "mesh/io/msh_reader.hpp"
#include "mesh/io/msh_writer.hpp"
#include "mesh/io/vtu_writer.hpp"
#include "mesh/primitives.hpp"
#include "mesh/volume_mesh.hpp"
#include "tests/test_support.hpp"
#include "tests/volume_mesh_files.hpp"

namespace fs = std::filesystem;
using namespace tetfsi;
using namespace tetfsi::mesh;

namespace {

TetMesh box_tets() {
  MeshSizing sizing;
  sizing.edge_length = 0.1;
  TetMesh m = mesh_solid(make_box({0.4, 0.2, 0.2}), sizing);
  m.subdomain.clear();
  return m;
}

TetMesh one_tet() {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  return m;
}

std::string check_error(TetMesh m) {
  std::vector<std::string> warnings;
  try {
    check_volume_mesh(m, "m.vtu", warnings);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(VolumeMesh, EveryFormatReadsBackTheGeneratedMesh) {
  const TetMesh m = box_tets();
  ASSERT_GT(m.num_tets(), 50);
  test::TempDir dir("volume_mesh");
  io::write_vtu(dir.path() / "binary.vtu", io::make_grid(m));
  test::write_vtu_ascii(dir.path() / "ascii.vtu", m);
  test::write_vtu_appended(dir.path() / "appended.vtu", m);
  io::write_msh(dir.path() / "v41.msh", m, io::MshVersion::k41);
  io::write_msh(dir.path() / "v22.msh", m, io::MshVersion::k22);
  for (const char* name : {"binary.vtu", "ascii.vtu", "appended.vtu", "v41.msh", "v22.msh"}) {
    std::vector<std::string> warnings;
    const TetMesh back = import_volume_mesh((dir.path() / name).string(), {}, warnings);
    EXPECT_TRUE(warnings.empty()) << name << ": " << warnings.front();
    ASSERT_EQ(back.num_vertices(), m.num_vertices()) << name;
    ASSERT_EQ(back.num_tets(), m.num_tets()) << name;
    for (int i = 0; i < m.num_vertices(); ++i) ASSERT_EQ(back.vertices[i], m.vertices[i]) << name << " node " << i;
    for (int t = 0; t < m.num_tets(); ++t) ASSERT_EQ(back.tets[t], m.tets[t]) << name << " tet " << t;
  }
}

TEST(VolumeMesh, PlacementScalesRotatesAndKeepsOrientation) {
  test::TempDir dir("volume_mesh_place");
  const TetMesh m = box_tets();
  io::write_msh(dir.path() / "m.msh", m);
  Placement p;
  p.unit_scale = 0.01;
  p.rotation_deg = {30, 30, 0};
  p.translation = {1, 2, 3};
  std::vector<std::string> warnings;
  const TetMesh back = import_volume_mesh((dir.path() / "m.msh").string(), p, warnings);
  const Eigen::Matrix3d R = placement_rotation(p.rotation_deg);
  double v0 = 0, v1 = 0;
  for (int t = 0; t < m.num_tets(); ++t) v0 += signed_volume(m, t), v1 += signed_volume(back, t);
  EXPECT_NEAR(v1, 1e-6 * v0, 1e-12 * v0);  // scale^3
  EXPECT_NEAR(v0, 0.4 * 0.2 * 0.2, 1e-12);
  for (int i = 0; i < m.num_vertices(); ++i)
    EXPECT_LT((back.vertices[i] - (R * (0.01 * m.vertices[i]) + p.translation)).norm(), 1e-14);
}

TEST(VolumeMesh, ChecksRefuseDefectsAndRepairWhatTheyCan) {
  // Every tet negative: reordered, with a warning.
  TetMesh flipped = box_tets();
  for (auto& t : flipped.tets) std::swap(t[0], t[1]);
  std::vector<std::string> warnings;
  check_volume_mesh(flipped, "m.vtu", warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("negatively oriented"), std::string::npos);
  for (int t = 0; t < flipped.num_tets(); ++t) EXPECT_GT(signed_volume(flipped, t), 0);
  // One inverted tet among positive ones.
  TetMesh tangled = box_tets();
  std::swap(tangled.tets[7][0], tangled.tets[7][1]);
  EXPECT_NE(check_error(tangled).find("tet 7 is inverted"), std::string::npos) << check_error(tangled);
  // A flat tet.
  TetMesh flat = one_tet();
  flat.vertices[3] = {0.5, 0.5, 0};
  EXPECT_NE(check_error(flat).find("tet 0 is degenerate"), std::string::npos) << check_error(flat);
  TetMesh repeated = one_tet();
  repeated.tets[0][3] = 0;
  EXPECT_NE(check_error(repeated).find("repeats a node"), std::string::npos);
  EXPECT_NE(check_error(TetMesh{}).find("no tetrahedra"), std::string::npos);
  // Two tets apart.
  TetMesh two = one_tet();
  for (int i = 0; i < 4; ++i) two.vertices.push_back(two.vertices[i] + Eigen::Vector3d(5, 0, 0));
  two.tets.push_back({4, 5, 6, 7});
  EXPECT_NE(check_error(two).find("2 separate pieces"), std::string::npos) << check_error(two);
  // Three tets on one face.
  TetMesh fan = one_tet();
  fan.vertices.push_back({0.2, 0.2, 0.5});
  fan.vertices.push_back({0.1, 0.1, 0.6});
  fan.tets.push_back({0, 1, 2, 4});
  fan.tets.push_back({0, 1, 2, 5});
  EXPECT_NE(check_error(fan).find("shared by more than two tets"), std::string::npos) << check_error(fan);
  // An unused node is dropped, the tets renumbered.
  TetMesh loose = one_tet();
  loose.vertices.insert(loose.vertices.begin(), Eigen::Vector3d(9, 9, 9));
  for (int& a : loose.tets[0]) ++a;
  warnings.clear();
  check_volume_mesh(loose, "m.vtu", warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 node(s) used by no tet"), std::string::npos);
  EXPECT_EQ(loose.num_vertices(), 4);
  EXPECT_EQ(loose.tets[0], (std::array<int, 4>{0, 1, 2, 3}));
}

TEST(VolumeMesh, GmshFilesKeepTetsIgnoreBoundaryElementsAndRefuseOtherSolids) {
  // 4.1 with non-contiguous node tags, a triangle block (ignored) and a tet block.
  const std::string v41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$Entities
0 0 0 1
1 0 0 0 1 1 1 0 0
$EndEntities
$Nodes
1 4 10 40
3 1 0 4
10
20
30
40
0 0 0
1 0 0
0 1 0
0 0 1
$EndNodes
$Elements
2 2 1 2
2 1 2 1
1 10 20 30
3 1 4 1
2 10 20 30 40
$EndElements
)";
  const TetMesh m = io::parse_msh_tets(v41, "a.msh");
  ASSERT_EQ(m.num_tets(), 1);
  EXPECT_EQ(m.tets[0], (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_GT(signed_volume(m, 0), 0);
  // 2.2 with a hexahedron: refused naming the element and its type.
  const std::string v22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
                          "5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n$EndNodes\n$Elements\n2\n1 15 2 0 1 1\n"
                          "7 5 2 1 1 1 2 3 4 5 6 7 8\n$EndElements\n";
  try {
    io::parse_msh_tets(v22, "b.msh");
    ADD_FAILURE() << "a hexahedron was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("element 7 has Gmsh type 5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::parse_msh_tets("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", "c.msh"), std::runtime_error);
  EXPECT_THROW(io::parse_msh_tets("$MeshFormat\n3.0 0 8\n$EndMeshFormat\n", "d.msh"), std::runtime_error);
  EXPECT_THROW(read_volume_mesh("/nonexistent/e.msh"), MeshError);
}

// Found by fuzz_msh (issue 44): a 4.1 node block claiming 8.7e12 nodes made the reader allocate
// 8 bytes per claimed tag before reading any (std::bad_alloc here; gigabytes for a count near 1e9).
// Counts the file cannot hold must end in a message naming what is missing, as 2.2's do.
TEST(VolumeMesh, GmshCountsTheFileCannotHoldAreRefused) {
  const std::string head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 8 1 8\n3 1 0 ";
  for (const std::string count : {"8666666666666", "4611686018427387904"}) {
    SCOPED_TRACE(count);
    try {
      io::parse_msh_tets(head + count + "\n1\n2\n0 0 0\n", "big.msh");
      ADD_FAILURE() << "accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("read_msh(big.msh): expected a node tag"), std::string::npos) << e.what();
    }
  }
  try {
    io::parse_msh_tets("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8666666666666\n1 0 0 0\n", "big.msh");
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("expected a node tag"), std::string::npos) << e.what();
  }
}

TEST(VolumeMesh, VtuOtherCellTypesAreRefusedNamingTheCell) {
  test::TempDir dir("volume_mesh_cells");
  const TetMesh m = one_tet();
  test::write_vtu_ascii(dir.path() / "mixed.vtu", m.vertices, {{0, 1, 2, 3}, {0, 1, 2}}, {10, 5});
  try {
    read_volume_mesh((dir.path() / "mixed.vtu").string());
    ADD_FAILURE() << "a triangle cell was accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("cell 1 has VTK type 5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mixed.vtu"), std::string::npos) << e.what();
  }
}
