// libFuzzer target: any bytes as a PLY file. Every input must end in a surface or a MeshError.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "mesh/complex_mesher.hpp"
#include "mesh/io/ply_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    tetfsi::mesh::io::parse_ply(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ply");
  } catch (const tetfsi::mesh::MeshError&) {
  }
  return 0;
}
