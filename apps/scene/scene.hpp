#pragma once
/// @file scene.hpp
/// Loading a scene file: parse (nlohmann-json), validate against the schema, fill in defaults.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::scene {

/// A validated scene: every key of the schema that has a default is present, file paths are
/// absolute. Runners read it with json.at(...) (validation guarantees types and ranges).
struct Scene {
  std::filesystem::path file;  ///< the scene file
  Json json;                   ///< resolved scene
  Json input;                  ///< the scene as written (no defaults): which blocks the user gave

  const Json& operator[](const char* block) const { return json.at(block); }
};

/// Thrown by load_scene with every problem found; what() lists them one per line as
/// "scene.json: /pointer: message".
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::vector<Issue> issues);
  const std::vector<Issue>& issues() const { return issues_; }

 private:
  std::vector<Issue> issues_;
};

/// Largest scene file read [bytes] (a scene holds keys and values; geometry is in surface files).
constexpr std::size_t kMaxSceneBytes = std::size_t(8) << 20;
/// Problems listed by SceneError::what() (all are kept in issues()).
constexpr std::size_t kMaxIssuesShown = 50;
/// Largest export.liquid_surface.smoothing in voxels of its voxel_size: the smoothing takes
/// 3 (smoothing / voxel_size)^2 explicit heat-equation steps (fluid/io/surface_voxels.hpp), 300
/// at this limit, on a band of 3 smoothing around the surface.
constexpr double kMaxSmoothingVoxels = 10;

/// Reads, parses and validates a scene file. Only regular files of at most kMaxSceneBytes are
/// read (a FIFO or device is refused before it is opened for reading).
/// @throws SceneError on unreadable files, JSON syntax errors (with line and column) and every
///         schema violation
Scene load_scene(const std::filesystem::path& file);

/// Validates JSON text as if read from `file` (used by load_scene and tests).
Scene parse_scene(const std::string& text, const std::filesystem::path& file);

/// 1-based line and column of byte offset `byte` in `text`.
std::pair<int, int> line_column(const std::string& text, std::size_t byte);

}  // namespace tetfsi::scene
