// libFuzzer target: any bytes as a Gmsh .msh file (ASCII 2.2 or 4.1). The first byte picks the
// reader: even, mesh::io::parse_msh_tets (tet_fem solids); odd, parse_msh_hexes (hex8 solids);
// the rest is the file. One parse per input: both readers are the same parser with another
// wanted element type, and under ASan each thrown error costs system calls (unpoisoning the
// stacks), so parsing every input twice halved the executions per second.
// Every input must end in a mesh or a std::runtime_error naming the cause.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "mesh/io/msh_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] % 2 == 0) tetfsi::mesh::io::parse_msh_tets(text, "fuzz.msh");
    else tetfsi::mesh::io::parse_msh_hexes(text, "fuzz.msh");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
