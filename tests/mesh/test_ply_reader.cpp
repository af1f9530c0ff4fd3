// The PLY reader (mesh/io/ply_reader.hpp): ASCII and binary files of both byte orders read back
// as closed surfaces; cut, header-only and inconsistent files end in a MeshError naming the file
// (assimp looped forever on the header-only file and aborted on the cut one).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "mesh/io/ply_reader.hpp"
#include "mesh/io/ply_writer.hpp"
#include "mesh/primitives.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_import.hpp"
#include "tests/test_support.hpp"

namespace {

using tetfsi::mesh::MeshError;
using tetfsi::mesh::io::parse_ply;

const std::string kHeader =
    "ply\nformat ascii 1.0\ncomment unit tetrahedron\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kTetra = kHeader + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

std::string error_of(const std::string& content) {
  try {
    parse_ply(content, "t.ply");
  } catch (const MeshError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PlyReader, AsciiTetrahedronIsAClosedSurfaceOfVolumeOneSixth) {
  auto s = parse_ply(kTetra, "t.ply");
  ASSERT_EQ(s.num_vertices(), 4);
  ASSERT_EQ(s.num_triangles(), 4);
  EXPECT_TRUE(tetfsi::mesh::validate_surface(s, "t.ply").empty());
  EXPECT_NEAR(tetfsi::mesh::enclosed_volume(s), 1.0 / 6.0, 1e-15);
}

TEST(PlyReader, QuadsAreSplitIntoFansAndExtraPropertiesSkipped) {
  const std::string cube =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
      "property uchar red\nelement face 6\nproperty list uchar uint vertex_index\nproperty float quality\n"
      "end_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n0 0 1 5\n1 0 1 6\n1 1 1 7\n0 1 1 8\n"
      "4 0 3 2 1 0.5\n4 4 5 6 7 0.5\n4 0 1 5 4 0.5\n4 1 2 6 5 0.5\n4 2 3 7 6 0.5\n4 3 0 4 7 0.5\n";
  auto s = parse_ply(cube, "cube.ply");
  EXPECT_EQ(s.num_triangles(), 12);
  EXPECT_TRUE(tetfsi::mesh::validate_surface(s, "cube.ply").empty());
  EXPECT_NEAR(tetfsi::mesh::enclosed_volume(s), 1.0, 1e-14);
}

TEST(PlyReader, BinaryBothByteOrdersReadBackWhatWasWritten) {
  tetfsi::test::TempDir dir("ply_reader");
  const auto box = tetfsi::mesh::make_box({0.3, 0.2, 0.1});
  const auto file = dir.path() / "box.ply";
  tetfsi::mesh::io::write_ply(file, box);  // binary little-endian, float
  const auto s = tetfsi::mesh::io::read_ply(file.string());
  ASSERT_EQ(s.num_vertices(), box.num_vertices());
  ASSERT_EQ(s.triangles, box.triangles);
  for (int i = 0; i < s.num_vertices(); ++i)
    EXPECT_LT((s.vertices[i] - box.vertices[i]).norm(), 1e-7);

  // The same tetrahedron in big-endian doubles and int32 indices.
  std::string big = "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                    "property double z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&big](const void* p, int n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (int i = n - 1; i >= 0; --i) big.push_back(static_cast<char>(b[i]));  // host is little-endian
  };
  const double xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& v : xyz)
    for (double c : v) put(&c, 8);
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& f : faces) {
    big.push_back(3);
    for (int i : f) put(&i, 4);
  }
  const auto t = parse_ply(big, "big.ply");
  EXPECT_NEAR(tetfsi::mesh::enclosed_volume(t), 1.0 / 6.0, 1e-15);
}

TEST(PlyReader, MalformedFilesNameTheFileAndTheDefect) {
  EXPECT_NE(error_of("ply\nformat ascii 1.0\n").find("t.ply: PLY header: no \"end_header\""), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0 0 0\n1 0 0\n0 1").find("the file ends before the vertex list"), std::string::npos);
  EXPECT_NE(error_of(kHeader + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1").find("the face list"), std::string::npos);
  std::string bad = kTetra;
  bad.replace(bad.find("3 1 2 3"), 7, "3 1 2 9");
  EXPECT_NE(error_of(bad).find("face 3 refers to vertex 9 of 4"), std::string::npos);
  bad = kTetra;
  bad.replace(bad.find("3 1 2 3"), 7, "2 1 2  ");
  EXPECT_NE(error_of(bad).find("face 3 has 2 vertices"), std::string::npos);
  bad = kTetra;
  bad.replace(bad.find("0 0 1\n"), 6, "0 0 nan\n");
  EXPECT_NE(error_of(bad).find("vertex 3 has a non-finite coordinate"), std::string::npos);
  // A count far beyond the file's size is refused before anything is allocated for it.
  bad = kTetra;
  bad.replace(bad.find("vertex 4"), 8, "vertex 999999999999");
  EXPECT_NE(error_of(bad).find("claims 999999999999 items"), std::string::npos);
  EXPECT_NE(error_of("plx\n").find("the first line must be \"ply\""), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 2.0\nend_header\n").find("version"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n")
                .find("line 4: expected \"property <type> <name>\""), std::string::npos);
}

TEST(PlyReader, ImportSurfaceUsesItForPlyFiles) {
  tetfsi::test::TempDir dir("ply_import");
  const auto file = dir.path() / "header_only.ply";
  std::ofstream(file) << "ply\nformat ascii 1.0\n";
  try {
    tetfsi::mesh::import_surface(file.string());
    FAIL() << "expected a MeshError";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("header_only.ply: PLY header"), std::string::npos) << e.what();
  }
  std::ofstream(dir.path() / "t.ply") << kTetra;
  tetfsi::mesh::Placement place;
  place.translation = {1, 2, 3};
  const auto s = tetfsi::mesh::import_surface((dir.path() / "t.ply").string(), place);
  EXPECT_EQ(s.vertices[0], Eigen::Vector3d(1, 2, 3));
}
