// VTU/PVD output is read back with VTK's own reader and matches what was written.
#include <gtest/gtest.h>

#include <fstream>

#include "mesh/io/vtu_writer.hpp"
#include "tests/test_support.hpp"

using namespace tetfsi::mesh;

namespace {

// Two tets sharing a face, with one point field and one cell field.
TetMesh two_tets() {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.subdomain = {1, 2};
  return m;
}

}  // namespace

TEST(VtuWriter, VtkReaderSeesWhatWasWritten) {
  tetfsi::test::TempDir dir("vtu");
  TetMesh m = two_tets();
  ASSERT_GT(signed_volume(m, 0), 0.0);
  auto grid = io::make_grid(m);
  std::vector<double> velocity;
  for (int i = 0; i < m.num_vertices(); ++i) velocity.insert(velocity.end(), {1.0 * i, 0.5, -2.0});
  grid.add_point_data("velocity", 3, velocity);
  const auto file = dir.path() / "frame_00000.vtu";
  io::write_vtu(file, grid);

  int status = -1;
  const std::string info = tetfsi::test::vtk_describe(file, &status);
  ASSERT_EQ(status, 0) << info;
  EXPECT_EQ(info, "5 2 p:velocity:3 c:subdomain:1\n");
}

TEST(VtuWriter, PvdListsEveryFrameWithItsTime) {
  tetfsi::test::TempDir dir("pvd");
  io::PvdCollection pvd(dir.path() / "fluid.pvd");
  const auto grid = io::make_grid(two_tets());
  for (int frame = 0; frame < 3; ++frame) {
    const std::string name = "fluid_" + std::to_string(frame) + ".vtu";
    io::write_vtu(dir.path() / name, grid);
    pvd.add(0.25 * frame, name);
  }
  int status = -1;
  const std::string info = tetfsi::test::vtk_describe(pvd.path(), &status);
  ASSERT_EQ(status, 0) << info;
  EXPECT_EQ(info, "0 5 2 c:subdomain:1\n0.25 5 2 c:subdomain:1\n0.5 5 2 c:subdomain:1\n");
}

TEST(VtuWriter, RejectsFieldOfWrongSize) {
  auto grid = io::make_grid(two_tets());
  EXPECT_THROW(grid.add_point_data("bad", 3, std::vector<double>(4, 0.0)), std::invalid_argument);
}

TEST(VtuWriter, FailedWriteLeavesEarlierFileIntact) {
  tetfsi::test::TempDir dir("atomic");
  const auto file = dir.path() / "a.vtu";
  io::write_vtu(file, io::make_grid(two_tets()));
  std::ifstream in(file);
  const std::string before((std::istreambuf_iterator<char>(in)), {});
  auto bad = io::make_grid(two_tets());
  bad.connectivity[0] = 99;  // refers to a point that does not exist
  EXPECT_THROW(io::write_vtu(file, bad), std::invalid_argument);
  std::ifstream again(file);
  const std::string after((std::istreambuf_iterator<char>(again)), {});
  EXPECT_EQ(before, after);
}
