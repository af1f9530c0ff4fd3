#include "apps/scene/scene.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "apps/scene/validate.hpp"

namespace tetfsi::scene {
namespace {

std::string format_issues(const std::string& file, const std::vector<Issue>& issues) {
  std::string s;
  for (const auto& i : issues)
    s += (s.empty() ? "" : "\n") + (i.pointer.empty() ? fmt::format("{}: {}", file, i.message)
                                                     : fmt::format("{}: {}: {}", file, i.pointer, i.message));
  return s;
}

}  // namespace

SceneError::SceneError(std::string file, std::vector<Issue> issues)
    : std::runtime_error(format_issues(file, issues)), issues_(std::move(issues)) {}

std::pair<int, int> line_column(const std::string& text, std::size_t byte) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') { ++line; col = 1; } else { ++col; }
  }
  return {line, col};
}

Scene parse_scene(const std::string& text, const std::filesystem::path& file) {
  const std::string name = file.filename().string();
  Json input;
  try {
    input = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // nlohmann's byte offset points one past the offending character.
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    if (auto p = what.find("syntax error "); p != std::string::npos) what = what.substr(p + 13);
    throw SceneError(name, {{"", fmt::format("JSON syntax error at line {}, column {}: {}", line, col, what)}});
  }
  std::vector<Issue> issues;
  const auto base = std::filesystem::absolute(file).parent_path();
  Json resolved = validate(input, scene_schema(), base, issues);
  if (!issues.empty()) throw SceneError(name, std::move(issues));
  return Scene{file, std::move(resolved)};
}

Scene load_scene(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw SceneError(file.filename().string(),
                     {{"", fmt::format("cannot read the scene file {}", file.string())}});
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), file);
}

}  // namespace tetfsi::scene
