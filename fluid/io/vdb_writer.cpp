#include "fluid/io/vdb_writer.hpp"

#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Prune.h>

#include "mesh/io/atomic_file.hpp"

namespace tetfsi::fluid {
namespace {

constexpr float kHalfWidth = 3.0f;  ///< narrow band of the level set [voxels]

/// The UUID OpenVDB writes after magic (8 bytes), file version, library major and minor
/// (3 x 4 bytes) and the grid-offsets flag (1 byte): 36 ASCII characters (io/Archive.cc).
constexpr std::size_t kUuidOffset = 21, kUuidLength = 36;

/// FNV-1a (64 bit) of `s` from `seed`.
std::uint64_t fnv1a(const std::string& s, std::uint64_t seed) {
  std::uint64_t h = seed;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

/// Replaces the file's random UUID by a version-4-shaped one hashed from the rest of the file.
void make_uuid_deterministic(std::string& bytes, const std::string& name) {
  if (bytes.size() < kUuidOffset + kUuidLength || bytes[kUuidOffset + 8] != '-' || bytes[kUuidOffset + 23] != '-')
    throw std::runtime_error(name + ": unexpected OpenVDB header (no UUID at byte 21)");
  std::string rest = bytes;
  rest.replace(kUuidOffset, kUuidLength, kUuidLength, '0');
  const std::uint64_t a = fnv1a(rest, 14695981039346656037ull), b = fnv1a(rest, a);
  char hex[33];
  std::snprintf(hex, sizeof hex, "%016llx%016llx", static_cast<unsigned long long>(a), static_cast<unsigned long long>(b));
  std::string h(hex);
  h[12] = '4';                                 // version 4 layout
  h[16] = "89ab"[(h[16] - '0') & 3];           // RFC 4122 variant
  const std::string uuid = h.substr(0, 8) + "-" + h.substr(8, 4) + "-" + h.substr(12, 4) + "-" + h.substr(16, 4) + "-" +
                           h.substr(20, 12);
  bytes.replace(kUuidOffset, kUuidLength, uuid);
}

openvdb::FloatGrid::Ptr float_grid(const char* name, const openvdb::math::Transform::Ptr& xf) {
  auto g = openvdb::FloatGrid::create(0.0f);
  g->setName(name);
  g->setTransform(xf);
  return g;
}

}  // namespace

std::uintmax_t write_vdb(const std::filesystem::path& path, const VoxelSamples& s, const mesh::SurfaceMesh* surface) {
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  const auto xf = openvdb::math::Transform::createLinearTransform(s.voxel_size);

  auto density = float_grid("density", xf);
  density->setGridClass(openvdb::GRID_FOG_VOLUME);
  density->insertMeta("unit", openvdb::StringMetadata("1"));
  auto temperature = float_grid("temperature", xf);
  temperature->insertMeta("unit", openvdb::StringMetadata("K"));
  auto velocity = openvdb::Vec3fGrid::create(openvdb::Vec3f(0.0f));
  velocity->setName("velocity");
  velocity->setTransform(xf);
  velocity->setVectorType(openvdb::VEC_CONTRAVARIANT_RELATIVE);
  velocity->setIsInWorldSpace(true);
  velocity->insertMeta("unit", openvdb::StringMetadata("m/s"));
  {
    auto d = density->getAccessor();
    auto t = temperature->getAccessor();
    auto u = velocity->getAccessor();
    for (std::size_t v = 0; v < s.size(); ++v) {
      const openvdb::Coord c(s.index[v].x(), s.index[v].y(), s.index[v].z());
      d.setValue(c, s.smoke[v]);
      t.setValue(c, s.temperature[v]);
      u.setValue(c, openvdb::Vec3f(s.velocity[v].x(), s.velocity[v].y(), s.velocity[v].z()));
    }
  }
  openvdb::tools::prune(density->tree());
  openvdb::tools::prune(temperature->tree());
  openvdb::tools::prune(velocity->tree());
  openvdb::GridPtrVec grids{density, temperature, velocity};

  if (surface && surface->num_triangles() > 0) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    points.reserve(surface->vertices.size());
    for (const auto& x : surface->vertices) points.emplace_back(float(x.x()), float(x.y()), float(x.z()));
    triangles.reserve(surface->triangles.size());
    for (const auto& t : surface->triangles) triangles.emplace_back(t[0], t[1], t[2]);
    auto ls = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xf, points, triangles, kHalfWidth);
    ls->setName("surface");
    ls->insertMeta("unit", openvdb::StringMetadata("m"));
    grids.push_back(ls);
  }

  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  std::string bytes;
  try {
    openvdb::io::File file(tmp.string());
    file.setCompression(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    openvdb::MetaMap meta;
    meta.insertMeta("creator", openvdb::StringMetadata("tetfsi"));
    file.write(grids, meta);
    file.close();
    std::ifstream in(tmp, std::ios::binary);
    std::ostringstream all;
    all << in.rdbuf();
    bytes = all.str();
  } catch (const openvdb::Exception& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("cannot write '" + path.string() + "': " + e.what());
  }
  std::error_code ignored;
  std::filesystem::remove(tmp, ignored);
  make_uuid_deterministic(bytes, path.string());
  mesh::io::write_file_atomically(path, bytes);
  return bytes.size();
}

}  // namespace tetfsi::fluid
