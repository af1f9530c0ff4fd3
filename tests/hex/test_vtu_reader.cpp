// mesh/io/vtu_reader: reads back what vtu_writer writes (inline base64, UInt64 header), ASCII VTU,
// VTK-style separately encoded UInt32-header blocks, and refuses bad files with a message.
#include <gtest/gtest.h>

#include <fstream>

#include "../test_support.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "solid/hex/block_mesh.hpp"

using namespace tetfsi::mesh;

TEST(VtuReader, RoundTripsWriterOutput) {
  auto mesh = tetfsi::solid::hex::block_mesh({0, 0, 0}, {1, 2, 3}, 2, 3, 1);
  mesh.vertices[5].x() += 0.123456789012345;
  auto grid = io::make_grid(mesh);
  std::vector<double> field(3 * mesh.num_vertices());
  for (std::size_t i = 0; i < field.size(); ++i) field[i] = 0.1 * static_cast<double>(i) - 1.0 / 3.0;
  grid.add_point_data("displacement", 3, field);
  grid.add_cell_data("id", 1, std::vector<double>(mesh.num_hexes(), 7.5));
  tetfsi::test::TempDir dir("vtu_reader");
  io::write_vtu(dir.path() / "a.vtu", grid);
  const auto back = io::read_vtu(dir.path() / "a.vtu");
  ASSERT_EQ(back.num_points(), mesh.num_vertices());
  for (int i = 0; i < mesh.num_vertices(); ++i) EXPECT_EQ(back.points[i], mesh.vertices[i]);
  EXPECT_EQ(back.connectivity, grid.connectivity);
  EXPECT_EQ(back.offsets, grid.offsets);
  EXPECT_EQ(back.types, grid.types);
  ASSERT_EQ(back.point_data.size(), 1u);
  EXPECT_EQ(back.point_data[0].values, field);
  ASSERT_EQ(back.cell_data.size(), 1u);
  EXPECT_EQ(back.cell_data[0].values[0], 7.5);
  const HexMesh hm = io::read_hex_mesh_vtu(dir.path() / "a.vtu");
  EXPECT_EQ(hm.hexes, mesh.hexes);
}

TEST(VtuReader, ReadsAsciiAndVtkStyleBinary) {
  // One unit hexahedron; points ASCII, connectivity as VTK writes binary: UInt32 header and
  // payload base64-encoded separately. 8 Int32 indices 0..7 = 32 bytes.
  const std::string text = R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="8" NumberOfCells="1">
      <Points>
        <DataArray type="Float32" NumberOfComponents="3" format="ascii">
          0 0 0  1 0 0  1 1 0  0 1 0  0 0 1  1 0 1  1 1 1  0 1 1
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="binary">
          IAAAAA==AAAAAAEAAAACAAAAAwAAAAQAAAAFAAAABgAAAAcAAAA=
        </DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">8</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">12</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
)";
  const auto grid = io::parse_vtu(text);
  const HexMesh m = io::to_hex_mesh(grid);
  ASSERT_EQ(m.num_hexes(), 1);
  for (int a = 0; a < 8; ++a) EXPECT_EQ(m.hexes[0][a], a);
  EXPECT_EQ(m.vertices[6], Eigen::Vector3d(1, 1, 1));
}

TEST(VtuReader, RefusesBadFilesWithMessage) {
  auto expect_error = [](const std::string& text, const std::string& part) {
    try {
      io::parse_vtu(text, "bad.vtu");
      ADD_FAILURE() << "no error for: " << part;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expect_error("hello", "no <VTKFile>");
  expect_error(R"(<VTKFile type="UnstructuredGrid" compressor="vtkZLibDataCompressor"><Piece NumberOfPoints="0" NumberOfCells="0"></Piece></VTKFile>)",
               "compressed");
  expect_error(R"(<VTKFile type="UnstructuredGrid"><UnstructuredGrid><Piece NumberOfPoints="2" NumberOfCells="0"><Points>
<DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0</DataArray></Points></Piece></UnstructuredGrid></VTKFile>)",
               "<Points>");
  EXPECT_THROW(io::read_vtu("/nonexistent/file.vtu"), std::runtime_error);
  // A tet grid is not a hex mesh.
  TetMesh tets;
  tets.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tets.tets = {{0, 1, 2, 3}};
  EXPECT_THROW(io::to_hex_mesh(io::make_grid(tets)), std::runtime_error);
}
