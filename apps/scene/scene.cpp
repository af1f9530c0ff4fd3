#include "apps/scene/scene.hpp"

#include <fstream>
#include <set>
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

/// Parses JSON text, recording keys that appear twice in one object (nlohmann keeps the last
/// silently, which would hide a user's mistake) as issues with their JSON pointer.
Json parse_checking_duplicates(const std::string& text, std::vector<Issue>& issues) {
  struct Frame {
    bool array = false;
    long index = -1;
    std::string key;
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  auto pointer = [&] {
    std::string p;
    for (const auto& f : stack) p = f.array ? p + "/" + std::to_string(f.index) : pointer_append(p, f.key);
    return p;
  };
  using Event = Json::parse_event_t;
  Json::parser_callback_t cb = [&](int, Event event, Json& parsed) {
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        if (!stack.empty() && stack.back().array) ++stack.back().index;
        stack.emplace_back();
        stack.back().array = event == Event::array_start;
        break;
      case Event::key:
        stack.back().key = parsed.get<std::string>();
        if (!stack.back().keys.insert(stack.back().key).second)
          issues.push_back({pointer(), "duplicate key: it appears more than once in this object"});
        break;
      case Event::value:
        if (!stack.empty() && stack.back().array) ++stack.back().index;
        break;
      case Event::object_end:
      case Event::array_end:
        stack.pop_back();
        break;
    }
    return true;
  };
  return Json::parse(text, cb);
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
  std::vector<Issue> issues;
  try {
    input = parse_checking_duplicates(text, issues);
  } catch (const Json::parse_error& e) {
    // nlohmann's byte offset points one past the offending character.
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string what = e.what();
    if (auto p = what.find("syntax error "); p != std::string::npos) what = what.substr(p + 13);
    throw SceneError(name, {{"", fmt::format("JSON syntax error at line {}, column {}: {}", line, col, what)}});
  } catch (const Json::exception& e) {  // e.g. out_of_range.406: number overflow parsing '1e400'
    std::string what = e.what();
    if (auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    std::string where;
    if (auto q = what.find('\''); q != std::string::npos) {
      const auto literal = what.substr(q + 1, what.find('\'', q + 1) - q - 1);
      if (auto at = text.find(literal); !literal.empty() && at != std::string::npos) {
        const auto [line, col] = line_column(text, at);
        where = fmt::format(" at line {}, column {}", line, col);
      }
    }
    throw SceneError(name, {{"", fmt::format("JSON error{}: {}", where, what)}});
  }
  const auto base = std::filesystem::absolute(file).parent_path();
  Json resolved = validate(input, scene_schema(), base, issues);
  if (!issues.empty()) throw SceneError(name, std::move(issues));
  return Scene{file, std::move(resolved), std::move(input)};
}

Scene load_scene(const std::filesystem::path& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw SceneError(file.filename().string(),
                     {{"", fmt::format("{} is a folder; expected a scene file (.json)", file.string())}});
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw SceneError(file.filename().string(),
                     {{"", fmt::format("cannot read the scene file {}", file.string())}});
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), file);
}

}  // namespace tetfsi::scene
