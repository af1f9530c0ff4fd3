// libFuzzer target: any bytes as a .vtu file (ASCII, inline base64, raw appended, zlib-compressed).
// Every input must end in a grid or a std::runtime_error naming the cause.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "mesh/io/vtu_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    tetfsi::mesh::io::parse_vtu(std::string(reinterpret_cast<const char*>(data), size), "fuzz.vtu");
  } catch (const std::runtime_error&) {
  }
  return 0;
}
