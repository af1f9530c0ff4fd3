/// @file surface_import.cpp
#include "mesh/surface_import.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/io/ply_reader.hpp"

namespace tetfsi::mesh {

Eigen::Matrix3d placement_rotation(const Eigen::Vector3d& rotation_deg) {
  const Eigen::Vector3d r = rotation_deg * (M_PI / 180.0);
  return (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

void apply_placement(SurfaceMesh& surface, const Placement& placement) { apply_placement(surface.vertices, placement); }

void apply_placement(std::vector<Eigen::Vector3d>& points, const Placement& placement) {
  if (!(placement.unit_scale > 0.0) || !std::isfinite(placement.unit_scale))
    throw MeshError("placement: unit_scale must be > 0");
  if (!placement.rotation_deg.allFinite() || !placement.translation.allFinite())
    throw MeshError("placement: rotation and translation must be finite");
  const Eigen::Matrix3d R = placement_rotation(placement.rotation_deg);
  for (auto& v : points) v = R * (placement.unit_scale * v) + placement.translation;
}

namespace {

/// Joins vertices at identical positions (exact comparison: the file's own values), as assimp's
/// JoinIdenticalVertices does for the other formats.
SurfaceMesh join_identical_vertices(const SurfaceMesh& in) {
  SurfaceMesh s;
  std::map<std::array<double, 3>, int> index_of;
  std::vector<int> to(in.vertices.size());
  for (std::size_t i = 0; i < in.vertices.size(); ++i) {
    const auto& p = in.vertices[i];
    auto [it, inserted] = index_of.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, s.num_vertices());
    if (inserted) s.vertices.push_back(p);
    to[i] = it->second;
  }
  for (const auto& t : in.triangles) s.triangles.push_back({to[t[0]], to[t[1]], to[t[2]]});
  return s;
}

/// A PLY file by its extension or its first three bytes: either way it goes to io::read_ply, never
/// to assimp (whose PLY reader also leaks on a file that starts with "ply" but no line break).
bool is_ply(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".ply") return true;
  std::ifstream in(path, std::ios::binary);
  char head[3] = {};
  in.read(head, 3);
  return in.gcount() == 3 && std::string_view(head, 3) == "ply";
}

/// OFF files (by extension or first token) state their vertex and face counts up front, and
/// assimp 5.2 reserves memory for them before reading any: a file claiming 4e40 vertices took
/// 16 GB in 30 s (found by fuzz_surface). Each vertex line takes at least 6 bytes ("0 0 0\n") and
/// each face line 8 ("3 0 1 2\n"); counts the file cannot hold are refused before assimp sees it.
void check_off_counts(const std::string& path, std::uintmax_t bytes) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  std::istringstream words(head);
  std::string token;
  words >> token;
  // assimp picks its OFF reader by content too, whatever the extension (fuzz_surface: an OFF file
  // named .gltf): the first token is [STCN4n]*OFF in any case, digits may follow it.
  std::string key = token;
  for (char& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto letters = key.find_first_not_of("stcn4");
  const bool off = ext == ".off" || (letters != std::string::npos && key.compare(letters, 3, "off") == 0);
  if (!off) return;
  // Skip the OFF token (if any) and comment lines, then read the counts as written.
  std::string line;
  std::istringstream lines(head);
  double counts[2] = {0, 0};
  int found = 0;
  bool first = true;
  while (found < 2 && std::getline(lines, line)) {
    std::istringstream ws(line);
    std::string w;
    while (found < 2 && ws >> w) {
      if (w[0] == '#') break;
      if (first) {  // the keyword ([ST][C][N][4][n]OFF); assimp reads digits glued to it as the first count
        first = false;
        std::string lw = w;
        for (char& c : lw) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const auto at = lw.find("off");
        if (at != std::string::npos) {
          w = w.substr(at + 3);
          if (w.empty()) continue;
        }
      }
      char* end = nullptr;
      const double x = std::strtod(w.c_str(), &end);
      if (end == w.c_str()) return;  // not a count: assimp reports the syntax error
      counts[found++] = x;
    }
  }
  if (found < 2) return;
  if (!(counts[0] >= 0 && counts[1] >= 0 && 6 * counts[0] + 8 * counts[1] <= double(bytes)))
  {
    char msg[160];
    std::snprintf(msg, sizeof msg, "%.6g vertices and %.6g faces, more than its %ju bytes can hold", counts[0],
                  counts[1], bytes);
    throw MeshError(path + ": OFF header claims " + msg + " (the file is cut or malformed)");
  }
}

}  // namespace

SurfaceMesh import_surface(const std::string& path, const Placement& placement) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw MeshError(path + ": file not found");
  if (!std::filesystem::is_regular_file(path, ec))
    throw MeshError(path + ": not a regular file (a folder, FIFO or device cannot be a surface)");
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes > kMaxSurfaceBytes)
    throw MeshError(path + ": " + (ec ? ec.message() : std::to_string(bytes) + " bytes; surface files of more "
                                                          "than 1 GiB are refused"));
  // PLY files never reach assimp (its PLY reader loops or aborts on cut files, ply_reader.hpp).
  if (is_ply(path)) {
    SurfaceMesh s = join_identical_vertices(io::read_ply(path));
    apply_placement(s, placement);
    return s;
  }

  check_off_counts(path, bytes);
  Assimp::Importer importer;
  // Drop everything but positions so that JoinIdenticalVertices joins by position alone (STL and
  // others give every face its own vertices with their own normals).
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
                                  aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                  aiComponent_TEXTURES | aiComponent_LIGHTS | aiComponent_CAMERAS);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_SortByPType |
                                  aiProcess_PreTransformVertices | aiProcess_JoinIdenticalVertices |
                                  aiProcess_ValidateDataStructure);
  if (scene == nullptr)
    throw MeshError(path + ": cannot read the file as a 3D model (" + importer.GetErrorString() + ")");

  // Join vertices at identical positions across meshes (exact comparison: the file's own values).
  SurfaceMesh s;
  std::map<std::array<double, 3>, int> index_of;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    std::vector<int> local(mesh->mNumVertices);
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      const aiVector3D& p = mesh->mVertices[i];
      const std::array<double, 3> key{p.x, p.y, p.z};
      if (!std::isfinite(key[0]) || !std::isfinite(key[1]) || !std::isfinite(key[2]))
        throw MeshError(path + ": vertex " + std::to_string(i) + " of mesh " + std::to_string(m) +
                        " has a non-finite coordinate");
      auto [it, inserted] = index_of.emplace(key, s.num_vertices());
      if (inserted) s.vertices.emplace_back(key[0], key[1], key[2]);
      local[i] = it->second;
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      s.triangles.push_back({local[face.mIndices[0]], local[face.mIndices[1]], local[face.mIndices[2]]});
    }
  }
  if (s.triangles.empty()) throw MeshError(path + ": the file contains no triangles");
  // Vertices of dropped points/lines may remain; validate_surface() removes unused vertices.
  apply_placement(s, placement);
  return s;
}

}  // namespace tetfsi::mesh
