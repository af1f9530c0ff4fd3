// mesh/io/vtu_reader: reads back what vtu_writer writes (zlib-compressed raw appended data, and
// uncompressed inline base64, UInt64 header) bit for bit, ASCII VTU, VTK-style separately encoded
// UInt32-header blocks, and refuses bad files with a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "../test_support.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "mesh/io/zlib_blocks.hpp"
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

namespace {

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A tet grid whose fields span several 32 KiB zlib blocks (5000 points x 3 doubles = 120 kB) and
// hold values that must survive bit for bit: denormals, -0, extremes, non-terminating fractions.
io::UnstructuredGrid big_grid() {
  io::UnstructuredGrid g;
  const int n = 5000;
  for (int i = 0; i < n; ++i) g.points.emplace_back(std::sin(0.37 * i), 1.0 / (i + 3.0), 1e-3 * i);
  for (int i = 0; i + 3 < n; i += 2) g.add_cell(io::VtkCell::Tetra, std::array<int, 4>{i, i + 1, i + 2, i + 3});
  std::vector<double> v(3 * n);
  for (int i = 0; i < 3 * n; ++i) v[i] = std::exp(0.001 * i) - 1.0 / 7.0;
  v[0] = std::numeric_limits<double>::denorm_min();
  v[1] = -0.0;
  v[2] = std::numeric_limits<double>::max();
  v[3] = std::numeric_limits<double>::lowest();
  g.add_point_data("velocity", 3, v);
  g.add_point_data("zero", 1, std::vector<double>(n, 0.0));
  std::vector<double> c(g.num_cells());
  for (int t = 0; t < g.num_cells(); ++t) c[t] = std::sqrt(t + 0.5);
  g.add_cell_data("smoke", 1, c);
  return g;
}

// Same bits: values compared through their bit patterns (so -0 != +0 would show).
void expect_bitwise_equal(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(double))) << what;
}

void expect_same_grid(const io::UnstructuredGrid& a, const io::UnstructuredGrid& b) {
  ASSERT_EQ(a.num_points(), b.num_points());
  EXPECT_EQ(0, std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(a.points[0])));
  EXPECT_EQ(a.connectivity, b.connectivity);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.types, b.types);
  ASSERT_EQ(a.point_data.size(), b.point_data.size());
  for (std::size_t k = 0; k < a.point_data.size(); ++k) {
    EXPECT_EQ(a.point_data[k].name, b.point_data[k].name);
    EXPECT_EQ(a.point_data[k].components, b.point_data[k].components);
    expect_bitwise_equal(a.point_data[k].values, b.point_data[k].values, a.point_data[k].name);
  }
  ASSERT_EQ(a.cell_data.size(), b.cell_data.size());
  for (std::size_t k = 0; k < a.cell_data.size(); ++k) {
    EXPECT_EQ(a.cell_data[k].name, b.cell_data[k].name);
    expect_bitwise_equal(a.cell_data[k].values, b.cell_data[k].values, a.cell_data[k].name);
  }
}

// parse_vtu refuses `text` with a message containing `part`.
void expect_error(const std::string& text, const std::string& part) {
  try {
    io::parse_vtu(text, "bad.vtu");
    ADD_FAILURE() << "no error for: " << part;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(VtuReader, ZlibRoundTripIsBitwiseAndSmaller) {
  const auto grid = big_grid();
  tetfsi::test::TempDir dir("vtu_zlib");
  const auto zlib = dir.path() / "z.vtu", none = dir.path() / "n.vtu";
  const auto zlib_bytes = io::write_vtu(zlib, grid);  // the default
  const auto none_bytes = io::write_vtu(none, grid, io::VtuCompression::None);
  EXPECT_EQ(zlib_bytes, std::filesystem::file_size(zlib));
  EXPECT_EQ(none_bytes, std::filesystem::file_size(none));
  const std::string text = read_text(zlib);
  EXPECT_NE(text.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(text.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_EQ(read_text(none).find("compressor"), std::string::npos);
  expect_same_grid(io::read_vtu(zlib), grid);
  expect_same_grid(io::read_vtu(none), grid);
  // Connectivity, offsets, types and the zero field compress well; the smooth fields' mantissas
  // hardly at all (their first blocks shrink by less than 10%, so their other blocks are stored);
  // raw instead of base64 saves 1/4: 271,389 vs 537,894 bytes (0.50; 0.45 with every block
  // deflated).
  EXPECT_LT(static_cast<double>(zlib_bytes), 0.55 * static_cast<double>(none_bytes));
}

// export.precision "float32": every field value comes back as the nearest float (checked against
// an independent rounding, float(v) for values in range), finite values beyond the float range as
// +-FLT_MAX, NaN and +-inf unchanged; points, cells and types stay bit for bit. The relative error
// of each value is at most 2^-24. Both encodings; the zlib file is smaller than the Float64 one.
TEST(VtuReader, Float32FieldsAreTheNearestFloatAndPointsStayExact) {
  auto grid = big_grid();
  auto& v = grid.point_data[0].values;
  v[4] = std::numeric_limits<double>::infinity();
  v[5] = -std::numeric_limits<double>::infinity();
  v[6] = std::numeric_limits<double>::quiet_NaN();
  v[7] = 3.5e38;  // finite, beyond FLT_MAX = 3.40282e38
  v[8] = 1e-50;   // below the smallest float subnormal
  tetfsi::test::TempDir dir("vtu_float32");
  for (auto compression : {io::VtuCompression::Zlib, io::VtuCompression::None}) {
    const auto file = dir.path() / "f.vtu";
    const auto bytes32 = io::write_vtu(file, grid, compression, io::VtuPrecision::Float32);
    const std::string text = read_text(file);
    EXPECT_NE(text.find("type=\"Float32\" Name=\"velocity\""), std::string::npos);
    EXPECT_NE(text.find("type=\"Float64\" Name=\"Points\""), std::string::npos);
    const auto back = io::read_vtu(file);
    ASSERT_EQ(back.num_points(), grid.num_points());
    EXPECT_EQ(0, std::memcmp(back.points.data(), grid.points.data(), grid.points.size() * sizeof(grid.points[0])));
    EXPECT_EQ(back.connectivity, grid.connectivity);
    EXPECT_EQ(back.offsets, grid.offsets);
    EXPECT_EQ(back.types, grid.types);
    ASSERT_EQ(back.point_data.size(), grid.point_data.size());
    ASSERT_EQ(back.cell_data.size(), grid.cell_data.size());
    double worst = 0;
    for (const auto* fields : {&grid.point_data, &grid.cell_data}) {
      const auto& read = fields == &grid.point_data ? back.point_data : back.cell_data;
      for (std::size_t k = 0; k < fields->size(); ++k) {
        const auto& a = (*fields)[k].values;
        const auto& b = read[k].values;
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); ++i) {
          if (std::isnan(a[i])) {
            EXPECT_TRUE(std::isnan(b[i])) << i;
          } else if (std::isfinite(a[i]) && std::abs(a[i]) > std::numeric_limits<float>::max()) {
            EXPECT_EQ(b[i], std::copysign(double(std::numeric_limits<float>::max()), a[i])) << i;
          } else {
            EXPECT_EQ(b[i], static_cast<double>(static_cast<float>(a[i]))) << i;
            if (std::isfinite(a[i]) && std::abs(a[i]) >= std::numeric_limits<float>::min())
              worst = std::max(worst, std::abs(b[i] - a[i]) / std::abs(a[i]));
          }
        }
      }
    }
    EXPECT_EQ(back.point_data[0].values[8], 0.0);
    EXPECT_LE(worst, std::ldexp(1.0, -24));
    EXPECT_GT(worst, 0.0);  // the fields were rounded
    const auto bytes64 = io::write_vtu(dir.path() / "d.vtu", grid, compression, io::VtuPrecision::Float64);
    EXPECT_LT(bytes32, bytes64);
  }
}

// ZlibStrategy::RleOrStored: an array whose bytes are noise (random floats: the first block
// shrinks by less than 10%) keeps its first block deflated and stores the others (a stored zlib
// stream is the bytes + 11: 2 header, 5 stored-block header, 4 Adler-32); an array of runs (zeros
// and a ramp of shared exponents) is compressed in every block; both inflate to their bytes.
TEST(VtuReader, ZlibBlocksStoreArraysThatDoNotCompress) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const std::size_t n = 5 * io::kVtkBlockSize / sizeof(float) + 123;  // 5 full blocks and a part
  std::vector<float> noise(n), runs(n, 0.0f);
  for (auto& x : noise) x = u(rng);
  for (std::size_t i = 0; i < n; i += 64) runs[i] = 293.15f + 1e-3f * static_cast<float>(i % 1000);
  for (const auto* values : {&noise, &runs}) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(values->data());
    const std::size_t size = values->size() * sizeof(float);
    std::string out;
    io::append_zlib_blocks(bytes, size, out, io::ZlibStrategy::RleOrStored);
    std::vector<std::uint64_t> header(3);
    std::memcpy(header.data(), out.data(), 3 * sizeof(std::uint64_t));
    ASSERT_EQ(header[0], 6u);
    ASSERT_EQ(header[2], size % io::kVtkBlockSize);
    std::vector<std::uint64_t> sizes(header[0]);
    std::memcpy(sizes.data(), out.data() + 3 * sizeof(std::uint64_t), sizes.size() * sizeof(std::uint64_t));
    std::size_t at = (3 + sizes.size()) * sizeof(std::uint64_t);
    std::vector<unsigned char> back(size);
    for (std::size_t b = 0; b < sizes.size(); ++b) {
      const std::size_t block = b + 1 < sizes.size() ? io::kVtkBlockSize : header[2];
      if (values == &noise) {
        if (b == 0) EXPECT_GT(sizes[b], 0.9 * block) << "noise: the first block is deflated, hardly smaller";
        else EXPECT_EQ(sizes[b], block + 11) << "noise: block " << b << " stored";
      } else {
        EXPECT_LT(sizes[b], 0.2 * block) << "runs: block " << b << " compressed";
      }
      ASSERT_TRUE(io::inflate_zlib_block(reinterpret_cast<const unsigned char*>(out.data()) + at, sizes[b],
                                         back.data() + b * io::kVtkBlockSize, block));
      at += sizes[b];
    }
    EXPECT_EQ(at, out.size());
    EXPECT_EQ(0, std::memcmp(back.data(), bytes, size));
  }
}

TEST(VtuReader, EmptyGridRoundTripsCompressed) {
  io::UnstructuredGrid empty;
  empty.add_point_data("p", 1, {});
  tetfsi::test::TempDir dir("vtu_empty");
  io::write_vtu(dir.path() / "e.vtu", empty);
  const auto back = io::read_vtu(dir.path() / "e.vtu");
  EXPECT_EQ(back.num_points(), 0);
  EXPECT_EQ(back.num_cells(), 0);
  ASSERT_EQ(back.point_data.size(), 1u);
  EXPECT_TRUE(back.point_data[0].values.empty());
}

TEST(VtuReader, CorruptCompressedDataIsRefused) {
  tetfsi::test::TempDir dir("vtu_corrupt");
  io::write_vtu(dir.path() / "z.vtu", big_grid());
  const std::string good = read_text(dir.path() / "z.vtu");
  // Flip bytes inside the first compressed block (after the 7 x 8-byte header of its 4 blocks).
  std::string flipped = good;
  const std::size_t data = good.find('_', good.find("<AppendedData")) + 1;
  for (std::size_t i = data + 100; i < data + 120; ++i) flipped[i] = static_cast<char>(~flipped[i]);
  expect_error(flipped, "corrupt");
  // Cut inside the first array read (the points), and before it.
  const std::size_t points_tag = good.find("offset=\"", good.find("Name=\"Points\"")) + 8;
  const std::size_t points = data + std::stoull(good.substr(points_tag, good.find('"', points_tag) - points_tag));
  expect_error(good.substr(0, points + 100), "truncated");
  expect_error(good.substr(0, points - 1), "offset past the appended data");
  // A block size no zlib stream of the stated compressed size can inflate to.
  std::string huge = good;
  const std::uint64_t block = std::uint64_t{1} << 62;
  std::memcpy(&huge[points + 8], &block, 8);
  expect_error(huge, "declares a block of 4611686018427387904 bytes");
  std::string lz4 = good;
  lz4.replace(lz4.find("vtkZLibDataCompressor"), 21, "vtkLZ4DataCompressor");
  expect_error(lz4, "vtkLZ4DataCompressor is not supported");
  std::string base64 = good;
  base64.replace(base64.find("encoding=\"raw\""), 14, "encoding=\"base64\"");
  expect_error(base64, "only raw");
}

// Bytes changed anywhere (header, XML, compression headers, blocks): a grid or a runtime_error
// naming the file, never another exception or a crash (scripts/fuzz.sh fuzz_vtu does this at length
// under the sanitizers).
TEST(VtuReader, DamagedCompressedFilesGiveAGridOrAnError) {
  io::UnstructuredGrid g;
  for (int i = 0; i < 40; ++i) g.points.emplace_back(0.1 * i, std::sin(i), 1.0);
  for (int i = 0; i + 3 < 40; ++i) g.add_cell(io::VtkCell::Tetra, std::array<int, 4>{i, i + 1, i + 2, i + 3});
  g.add_point_data("p", 1, std::vector<double>(40, 2.5));
  tetfsi::test::TempDir dir("vtu_damaged");
  io::write_vtu(dir.path() / "z.vtu", g);
  const std::string good = read_text(dir.path() / "z.vtu");
  std::uint64_t state = 12345;  // fixed LCG: the same damage on every run
  auto next = [&] { return (state = state * 6364136223846793005ull + 1442695040888963407ull) >> 33; };
  int errors = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::string text = good;
    for (int k = 0; k < 1 + trial % 4; ++k) text[next() % text.size()] = static_cast<char>(next());
    try {
      io::parse_vtu(text, "damaged.vtu");
    } catch (const std::runtime_error& e) {
      ++errors;
      EXPECT_NE(std::string(e.what()).find("damaged.vtu"), std::string::npos) << e.what();
    }
  }
  // Most damage is detected (zlib's Adler-32 guards each block): 1,872 of 2,000 here; the rest
  // still reads as a valid grid.
  EXPECT_GT(errors, 1700);
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
  expect_error("hello", "no <VTKFile>");
  expect_error(R"(<VTKFile type="UnstructuredGrid" compressor="vtkLZMADataCompressor"><Piece NumberOfPoints="0" NumberOfCells="0"></Piece></VTKFile>)",
               "not supported");
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
