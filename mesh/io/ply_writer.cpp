#include "mesh/io/ply_writer.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "mesh/io/atomic_file.hpp"

namespace tetfsi::mesh::io {
namespace {

bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// Appends the little-endian bytes of a float32 or int32 value.
template <class T>
void put(std::string& buf, T value) {
  static_assert(sizeof(T) == 4, "PLY writer stores 4-byte values");
  char bytes[4];
  std::memcpy(bytes, &value, 4);
  if (!host_is_little_endian()) std::swap(bytes[0], bytes[3]), std::swap(bytes[1], bytes[2]);
  buf.append(bytes, 4);
}

}  // namespace

void write_ply(const std::filesystem::path& path, const SurfaceMesh& surface,
               const std::vector<Eigen::Vector3d>& velocity) {
  const bool with_velocity = !velocity.empty();
  if (with_velocity && velocity.size() != surface.vertices.size())
    throw std::invalid_argument("write_ply: " + std::to_string(velocity.size()) + " velocities for " +
                                std::to_string(surface.vertices.size()) + " vertices");
  std::string data =
      "ply\nformat binary_little_endian 1.0\ncomment written by tetfsi, SI units (m, m/s)\n"
      "element vertex " + std::to_string(surface.vertices.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\n";
  if (with_velocity) data += "property float vx\nproperty float vy\nproperty float vz\n";
  data += "element face " + std::to_string(surface.triangles.size()) +
          "\nproperty list uchar int vertex_indices\nend_header\n";
  data.reserve(data.size() + surface.vertices.size() * 24 + surface.triangles.size() * 13);
  for (std::size_t i = 0; i < surface.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) put(data, static_cast<float>(surface.vertices[i][k]));
    if (with_velocity)
      for (int k = 0; k < 3; ++k) put(data, static_cast<float>(velocity[i][k]));
  }
  for (const auto& t : surface.triangles) {
    data.push_back(static_cast<char>(3));
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= surface.num_vertices())
        throw std::invalid_argument("write_ply: triangle index out of range");
      put(data, static_cast<std::int32_t>(t[k]));
    }
  }
  write_file_atomically(path, data);
}

}  // namespace tetfsi::mesh::io
