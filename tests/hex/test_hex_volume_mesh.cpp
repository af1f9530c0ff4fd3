// Hex meshes read from files (mesh/hex_volume_mesh.hpp): an irregular hex mesh of a box written as
// ASCII .vtu, library .vtu (zlib appended), Gmsh .msh 2.2 and 4.1 reads back node for node; the
// placement keeps every corner Jacobian positive; each check of check_hex_volume_mesh refuses its
// bad mesh naming the file and the element (or repairs it with a warning).
#include <gtest/gtest.h>

#include <fstream>

#include "mesh/complex_mesher.hpp"
#include "mesh/hex_volume_mesh.hpp"
#include "mesh/io/vtu_writer.hpp"
#include "mesh/volume_mesh.hpp"
#include "tests/hex_mesh_files.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi;
using namespace tetfsi::mesh;

namespace {

HexMesh unit_cube() { return solid::hex::block_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1, 1, 1); }

/// The MeshError message of check_hex_volume_mesh on `m` ("" if it passes).
std::string check_message(HexMesh m, std::vector<std::string>* warnings = nullptr) {
  std::vector<std::string> w;
  try {
    check_hex_volume_mesh(m, "m.vtu", warnings ? *warnings : w);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

void expect_refused(const HexMesh& m, const std::string& fragment) {
  const std::string msg = check_message(m);
  EXPECT_NE(msg.find("m.vtu: "), std::string::npos) << msg;
  EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
}

double min_corner_jacobian(const HexMesh& m) {
  double j = 1e300;
  for (const auto& h : m.hexes)
    for (int i = 0; i < 8; ++i) {
      const auto& n = kHexCornerNeighbours[i];
      Eigen::Matrix3d J;
      J << m.vertices[h[n[0]]] - m.vertices[h[i]], m.vertices[h[n[1]]] - m.vertices[h[i]],
          m.vertices[h[n[2]]] - m.vertices[h[i]];
      j = std::min(j, J.determinant());
    }
  return j;
}

}  // namespace

TEST(HexVolumeMesh, EveryFormatReadsBackNodeForNode) {
  const HexMesh m = test::jittered_block({0, 0, 0}, {0.3, 0.2, 0.2}, 3, 2, 2, 0.2);
  ASSERT_GT(min_corner_jacobian(m), 0);
  test::TempDir dir("hex_volume_mesh");
  test::write_vtu_ascii(dir.path() / "ascii.vtu", m);
  io::write_vtu(dir.path() / "zlib.vtu", io::make_grid(m));
  test::write_msh_hexes(dir.path() / "m22.msh", m, "2.2");
  test::write_msh_hexes(dir.path() / "m41.msh", m, "4.1");
  for (const char* name : {"ascii.vtu", "zlib.vtu", "m22.msh", "m41.msh"}) {
    SCOPED_TRACE(name);
    std::vector<std::string> warnings;
    const HexMesh back = import_hex_volume_mesh((dir.path() / name).string(), {}, warnings);
    EXPECT_TRUE(warnings.empty());
    ASSERT_EQ(back.num_vertices(), m.num_vertices());
    ASSERT_EQ(back.num_hexes(), m.num_hexes());
    for (int i = 0; i < m.num_vertices(); ++i) EXPECT_LE((back.vertices[i] - m.vertices[i]).norm(), 1e-15);
    EXPECT_EQ(back.hexes, m.hexes);
  }
}

TEST(HexVolumeMesh, PlacementRotatesScalesAndTranslates) {
  const HexMesh m = test::jittered_block({0, 0, 0}, {300, 200, 200}, 3, 2, 2, 0.2);  // millimetres
  test::TempDir dir("hex_volume_mesh_place");
  test::write_msh_hexes(dir.path() / "m.msh", m, "4.1");
  Placement p;
  p.unit_scale = 1e-3;
  p.rotation_deg = {30, 30, 0};
  p.translation = {1, -2, 0.5};
  std::vector<std::string> warnings;
  const HexMesh back = import_hex_volume_mesh((dir.path() / "m.msh").string(), p, warnings);
  const Eigen::Matrix3d R = placement_rotation(p.rotation_deg);
  for (int i = 0; i < m.num_vertices(); ++i)
    EXPECT_LE((back.vertices[i] - (R * (1e-3 * m.vertices[i]) + p.translation)).norm(), 1e-14);
  EXPECT_GT(min_corner_jacobian(back), 0);  // a rotation keeps the orientation
  EXPECT_TRUE(warnings.empty());
}

TEST(HexVolumeMesh, MirroredNumberingThroughoutIsReordered) {
  const HexMesh m = test::jittered_block({0, 0, 0}, {0.3, 0.2, 0.2}, 3, 2, 2, 0.2);
  HexMesh mirrored = m;
  for (auto& h : mirrored.hexes) h = {h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]};
  ASSERT_LT(min_corner_jacobian(mirrored), 0);
  std::vector<std::string> warnings;
  EXPECT_EQ(check_message(mirrored, &warnings), "");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("every hex was negatively oriented"), std::string::npos);
  std::vector<std::string> w;
  check_hex_volume_mesh(mirrored, "m.vtu", w);
  EXPECT_EQ(mirrored.hexes, m.hexes);
}

TEST(HexVolumeMesh, BadMeshesAreRefusedNamingTheElement) {
  HexMesh one_mirrored = test::jittered_block({0, 0, 0}, {0.3, 0.2, 0.2}, 3, 2, 2, 0.2);
  auto& h1 = one_mirrored.hexes[1];
  h1 = {h1[4], h1[5], h1[6], h1[7], h1[0], h1[1], h1[2], h1[3]};
  expect_refused(one_mirrored, "hex 1 is inverted: 1 of 12 hexes");

  HexMesh folded = unit_cube();  // node 4 pushed far below the bottom face: Gauss points of both signs
  folded.vertices[4] = {0, 0, -1.5};
  expect_refused(folded, "hex 0 is inverted or folded at its Gauss point 0 (xi, eta, zeta) = (-0.5774, -0.5774, -0.5774)");
  HexMesh corner = unit_cube();  // pushed less: its corner 0 is negative, every Gauss point positive
  corner.vertices[4] = {0, 0, -0.5};
  EXPECT_EQ(check_message(corner), "");

  HexMesh flat = unit_cube();  // top face collapsed onto the bottom one
  for (int i = 4; i < 8; ++i) flat.vertices[i].z() = 0;
  expect_refused(flat, "hex 0 is degenerate at its Gauss point 0 (xi, eta, zeta) = (-0.5774, -0.5774, -0.5774)");

  HexMesh repeated = unit_cube();
  repeated.hexes[0][6] = repeated.hexes[0][0];
  expect_refused(repeated, "hex 0 repeats a node");

  HexMesh missing = unit_cube();
  missing.hexes[0][3] = 8;
  expect_refused(missing, "hex 0 refers to a missing node");

  HexMesh nan = unit_cube();
  nan.vertices[2].x() = std::nan("");
  expect_refused(nan, "node 2 has a non-finite coordinate");

  // Two cubes side by side, each with its own 8 nodes: the shared face's nodes are duplicates.
  HexMesh split = unit_cube();
  for (int i = 0; i < 8; ++i) split.vertices.push_back(unit_cube().vertices[i] + Eigen::Vector3d(1, 0, 0));
  auto shifted = split.hexes[0];
  for (int& v : shifted) v += 8;
  split.hexes.push_back(shifted);
  expect_refused(split, "are duplicates (both at [1, ");

  HexMesh apart = split;  // the same cubes a gap apart
  for (int i = 8; i < 16; ++i) apart.vertices[i].x() += 0.5;
  expect_refused(apart, "the hexes form 2 separate pieces");

  HexMesh doubled = unit_cube();  // the same hex twice
  doubled.hexes.push_back(doubled.hexes[0]);
  expect_refused(doubled, "hex 1 has the same nodes as hex 0 (duplicate hexes)");
  HexMesh fan = unit_cube();  // two hexes of different heights on the cube's top face: three on one face
  const auto& h0 = fan.hexes[0];
  const std::array<int, 4> top{h0[4], h0[5], h0[6], h0[7]};
  for (double z : {2.0, 3.0}) {
    const int base = fan.num_vertices();
    for (int v : top) fan.vertices.push_back(Eigen::Vector3d(fan.vertices[v].x(), fan.vertices[v].y(), z));
    fan.hexes.push_back({top[0], top[1], top[2], top[3], base, base + 1, base + 2, base + 3});
  }
  expect_refused(fan, "the face (4, 5, 6, 7) of hex 2 is shared by more than two hexes (overlapping hexes)");

  expect_refused(HexMesh{}, "the mesh has no hexahedra");
}

TEST(HexVolumeMesh, UnusedNodesAreDroppedWithAWarning) {
  HexMesh m = unit_cube();
  m.vertices.insert(m.vertices.begin(), Eigen::Vector3d(5, 5, 5));  // node 0 unused
  for (int& v : m.hexes[0]) ++v;
  std::vector<std::string> warnings;
  check_hex_volume_mesh(m, "m.vtu", warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 node(s) used by no hex were dropped"), std::string::npos);
  EXPECT_EQ(m.hexes, unit_cube().hexes);
  EXPECT_EQ(m.num_vertices(), 8);
}

TEST(HexVolumeMesh, WrongCellTypesAndMissingFilesAreRefused) {
  test::TempDir dir("hex_volume_mesh_cells");
  const HexMesh cube = unit_cube();
  test::write_vtu_ascii(dir.path() / "hex.vtu", cube);
  test::write_msh_hexes(dir.path() / "hex.msh", cube, "2.2");
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  test::write_vtu_ascii(dir.path() / "tet.vtu", p, {{0, 1, 2, 3}}, {10});
  std::ofstream(dir.path() / "tet.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                                           "4 0 0 1\n$EndNodes\n$Elements\n1\n1 4 2 1 1 1 2 3 4\n$EndElements\n";
  auto message = [&](auto read, const char* name) {
    try {
      read((dir.path() / name).string());
    } catch (const MeshError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto hex = [](const std::string& f) { return read_hex_volume_mesh(f); };
  auto tet = [](const std::string& f) { return read_volume_mesh(f); };
  EXPECT_NE(message(hex, "tet.vtu").find("cell 0 has VTK type 10 with 4 points; only hexahedra"), std::string::npos);
  EXPECT_NE(message(hex, "tet.vtu").find("model \"tet_fem\""), std::string::npos);
  EXPECT_NE(message(hex, "tet.msh").find("element 1 has Gmsh type 4 (4-node tetrahedron); only 8-node hexahedra (type 5)"),
            std::string::npos) << message(hex, "tet.msh");
  EXPECT_NE(message(tet, "hex.vtu").find("model \"hex8\""), std::string::npos) << message(tet, "hex.vtu");
  EXPECT_NE(message(tet, "hex.msh").find("element 1 has Gmsh type 5 (8-node hexahedron)"), std::string::npos);
  EXPECT_NE(message(hex, "none.vtu").find("none.vtu: not found"), std::string::npos);
  EXPECT_NE(message(hex, "hex.obj").find("not found"), std::string::npos);
  EXPECT_EQ(message(hex, "hex.vtu"), "");
  EXPECT_EQ(message(hex, "hex.msh"), "");
}
