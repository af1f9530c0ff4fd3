// libFuzzer target: the surface import path of `tetfsi mesh` and of mesh geometry in scenes
// (mesh::import_surface: PLY by ply_reader, the other formats by assimp). The first byte picks
// the file extension, the rest is the file. Every input must end in a surface or a MeshError.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "mesh/complex_mesher.hpp"
#include "mesh/surface_import.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const extensions[] = {".obj", ".stl", ".off", ".ply", ".gltf", ".fbx"};
  const std::string path = "/dev/shm/tetfsi_fuzz_" + std::to_string(::getpid()) + extensions[data[0] % 6];
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    tetfsi::mesh::import_surface(path);
  } catch (const tetfsi::mesh::MeshError&) {
  }
  ::unlink(path.c_str());
  return 0;
}
