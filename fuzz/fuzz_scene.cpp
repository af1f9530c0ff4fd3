// libFuzzer target: any bytes as a scene file. Every input must end in a Scene or a SceneError
// (no crash, no other exception, no sanitizer report).
#include <cstddef>
#include <cstdint>
#include <string>

#include "apps/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    tetfsi::scene::parse_scene(text, "fuzz.json");
  } catch (const tetfsi::scene::SceneError&) {
  }
  return 0;
}
