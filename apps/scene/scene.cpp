#include "apps/scene/scene.hpp"

#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "apps/scene/validate.hpp"

namespace tetfsi::scene {
namespace {

/// At most `n` characters of `text` (a huge key in a pointer or message is not echoed whole).
std::string clip(const std::string& text, std::size_t n) {
  return text.size() <= n ? text : text.substr(0, n) + fmt::format("... ({} characters)", text.size());
}

std::string format_issues(const std::string& file, const std::vector<Issue>& issues) {
  std::string s;
  std::size_t shown = 0;
  for (const auto& i : issues) {
    if (++shown > kMaxIssuesShown) {
      s += fmt::format("\n{}: ... and {} more problem(s)", file, issues.size() - kMaxIssuesShown);
      break;
    }
    const std::string pointer = clip(i.pointer, 200), message = clip(i.message, 600);
    s += (s.empty() ? "" : "\n") + (pointer.empty() ? fmt::format("{}: {}", file, message)
                                                   : fmt::format("{}: {}: {}", file, pointer, message));
  }
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
  namespace fs = std::filesystem;
  const std::string name = file.filename().string();
  std::error_code ec;
  const auto status = fs::status(file, ec);
  if (fs::is_directory(status))
    throw SceneError(name, {{"", fmt::format("{} is a folder; expected a scene file (.json)", file.string())}});
  if (fs::exists(status) && !fs::is_regular_file(status))  // a FIFO would block, /dev/zero never ends
    throw SceneError(name, {{"", fmt::format("{} is not a regular file (a FIFO, socket or device); expected a "
                                             "scene file (.json)", file.string())}});
  std::ifstream in(file, std::ios::binary);
  if (!in || !fs::exists(status))
    throw SceneError(name, {{"", fmt::format("cannot read the scene file {}", file.string())}});
  // Read at most one byte more than allowed, whatever the file system says about the size.
  std::string text(kMaxSceneBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxSceneBytes)
    throw SceneError(name, {{"", fmt::format("{} is larger than {} MiB; a scene file holds keys and values, "
                                             "geometry belongs in surface files (solids/i/geometry/file)",
                                             file.string(), kMaxSceneBytes >> 20)}});
  return parse_scene(text, file);
}

}  // namespace tetfsi::scene
