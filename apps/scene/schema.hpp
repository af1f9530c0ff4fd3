#pragma once
/// @file schema.hpp
/// A small declarative description of the scene file: each key with its type, unit, default,
/// range, allowed values and children. The same description drives validation (validate.hpp)
/// and the key reference in docs/scene_format.md (docs.hpp), so the two cannot drift apart.
///
/// Hand-written rather than JSON Schema + valijson: we want errors with units, ranges in SI
/// words, "did you mean" hints and defaults filled in, and Markdown docs from the same source.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tetfsi::scene {

using Json = nlohmann::json;

/// What a key holds.
enum class Kind {
  Number,   ///< a real number (JSON number)
  Integer,  ///< an integer
  Bool,     ///< true / false
  String,   ///< free text
  Enum,     ///< one of `choices`
  EnumSet,  ///< a non-empty array of distinct values from `choices` (e.g. ["x", "z"])
  File,     ///< a file path, resolved relative to the scene file's folder; must exist
  Vector,   ///< a fixed-length array of numbers (`length`)
  Object,   ///< an object with the keys `members`
  Array,    ///< an array of objects, each described by `element`
};

/// One validation problem: where (JSON pointer) and what.
struct Issue {
  std::string pointer;
  std::string message;
};

struct Field;
/// A cross-key check on a validated object (e.g. lo < hi); adds issues for the object's pointer.
using Check = std::function<void(const Json& object, const std::string& pointer,
                                 std::vector<Issue>& issues)>;

/// One key of the scene file.
struct Field {
  std::string key;
  Kind kind = Kind::Number;
  std::string unit;                 ///< SI unit ("m", "kg/m^3", ...); empty: dimensionless
  std::string doc;                  ///< one sentence
  bool required = false;
  Json default_value;               ///< null: no default (key stays absent unless given)
  std::optional<double> gt, ge, lt, le;  ///< range of numbers (and of each Vector component)
  std::vector<std::string> choices;     ///< Enum values
  int length = 0;                       ///< Vector length
  int min_items = 0;                    ///< Array: minimum number of elements
  std::vector<Field> members;           ///< Object members (common to every variant)
  /// Tagged objects: the member `tag` (an Enum among members) selects extra members.
  std::string tag;
  std::map<std::string, std::vector<Field>> variants;
  std::vector<Check> checks;            ///< Object: cross-key checks after the members passed
  std::shared_ptr<Field> element;       ///< Array: description of each element (an Object)

  // Builders, so that block files read like a table.
  static Field number(std::string key, std::string unit, std::string doc);
  static Field integer(std::string key, std::string doc);
  static Field boolean(std::string key, std::string doc);
  static Field string(std::string key, std::string doc);
  static Field enumeration(std::string key, std::vector<std::string> choices, std::string doc);
  /// A non-empty array of distinct values from `choices` (Kind::EnumSet).
  static Field enumeration_set(std::string key, std::vector<std::string> choices, std::string doc);
  static Field file(std::string key, std::string doc);
  static Field vector(std::string key, int length, std::string unit, std::string doc);
  static Field object(std::string key, std::string doc, std::vector<Field> members);
  /// Array of objects; `element_members` describe each element.
  static Field array(std::string key, std::string doc, Field element);

  Field&& def(Json value) && { default_value = std::move(value); return std::move(*this); }
  Field&& req() && { required = true; return std::move(*this); }
  Field&& greater(double v) && { gt = v; return std::move(*this); }
  Field&& at_least(double v) && { ge = v; return std::move(*this); }
  Field&& less(double v) && { lt = v; return std::move(*this); }
  Field&& at_most(double v) && { le = v; return std::move(*this); }
  Field&& items(int n) && { min_items = n; return std::move(*this); }
  /// EnumSet: an empty array is valid when it is the default (e.g. "compare nothing").
  bool empty_set_allowed() const { return default_value.is_array() && default_value.empty(); }
  Field&& variant(std::string tag_value, std::vector<Field> extra) && {
    variants[std::move(tag_value)] = std::move(extra);
    return std::move(*this);
  }
  Field&& tagged_by(std::string tag_key) && { tag = std::move(tag_key); return std::move(*this); }
  Field&& check(Check c) && { checks.push_back(std::move(c)); return std::move(*this); }

  /// "a number > 0 and < 0.5", "one of none, smoke, liquid", ... (used in errors and docs).
  std::string expectation() const;
  /// The range alone, e.g. "> 0, < 0.5"; empty if none.
  std::string range_text() const;
};

/// The whole scene file (top-level object); defined in scene_schema.cpp from the block files.
const Field& scene_schema();

/// Appends "/key" to a JSON pointer, escaping '~' and '/' (RFC 6901).
std::string pointer_append(const std::string& pointer, const std::string& key);

}  // namespace tetfsi::scene
