#include "apps/scene/schema.hpp"

#include <fmt/format.h>

namespace tetfsi::scene {
namespace {

Field make(std::string key, Kind kind, std::string unit, std::string doc) {
  Field f;
  f.key = std::move(key);
  f.kind = kind;
  f.unit = std::move(unit);
  f.doc = std::move(doc);
  return f;
}

std::string num(double v) { return fmt::format("{:g}", v); }

}  // namespace

Field Field::number(std::string key, std::string unit, std::string doc) {
  return make(std::move(key), Kind::Number, std::move(unit), std::move(doc));
}
Field Field::integer(std::string key, std::string doc) {
  return make(std::move(key), Kind::Integer, "", std::move(doc));
}
Field Field::boolean(std::string key, std::string doc) {
  return make(std::move(key), Kind::Bool, "", std::move(doc));
}
Field Field::string(std::string key, std::string doc) {
  return make(std::move(key), Kind::String, "", std::move(doc));
}
Field Field::enumeration(std::string key, std::vector<std::string> choices, std::string doc) {
  Field f = make(std::move(key), Kind::Enum, "", std::move(doc));
  f.choices = std::move(choices);
  return f;
}
Field Field::enumeration_set(std::string key, std::vector<std::string> choices, std::string doc) {
  Field f = make(std::move(key), Kind::EnumSet, "", std::move(doc));
  f.choices = std::move(choices);
  return f;
}
Field Field::file(std::string key, std::string doc) {
  return make(std::move(key), Kind::File, "", std::move(doc));
}
Field Field::vector(std::string key, int length, std::string unit, std::string doc) {
  Field f = make(std::move(key), Kind::Vector, std::move(unit), std::move(doc));
  f.length = length;
  return f;
}
Field Field::object(std::string key, std::string doc, std::vector<Field> members) {
  Field f = make(std::move(key), Kind::Object, "", std::move(doc));
  f.members = std::move(members);
  return f;
}
Field Field::array(std::string key, std::string doc, Field element) {
  Field f = make(std::move(key), Kind::Array, "", std::move(doc));
  f.element = std::make_shared<Field>(std::move(element));
  return f;
}

std::string Field::range_text() const {
  std::vector<std::string> parts;
  if (gt) parts.push_back("> " + num(*gt));
  if (ge) parts.push_back(">= " + num(*ge));
  if (lt) parts.push_back("< " + num(*lt));
  if (le) parts.push_back("<= " + num(*le));
  std::string s;
  for (std::size_t i = 0; i < parts.size(); ++i) s += (i ? " and " : "") + parts[i];
  return s;
}

std::string Field::expectation() const {
  const std::string range = range_text();
  const std::string ranged = range.empty() ? "" : " " + range;
  switch (kind) {
    case Kind::Number: return "a number" + ranged;
    case Kind::Integer: return "an integer" + ranged;
    case Kind::Bool: return "true or false";
    case Kind::String: return "a string";
    case Kind::File: return "a file path (relative to the scene file's folder)";
    case Kind::Enum: {
      std::string s = "one of ";
      for (std::size_t i = 0; i < choices.size(); ++i) s += (i ? ", \"" : "\"") + choices[i] + "\"";
      return s;
    }
    case Kind::EnumSet: {
      std::string s = empty_set_allowed() ? "an array of distinct values from " : "a non-empty array of distinct values from ";
      for (std::size_t i = 0; i < choices.size(); ++i) s += (i ? ", \"" : "\"") + choices[i] + "\"";
      return s;
    }
    case Kind::Vector:
      return fmt::format("an array of {} numbers{}", length, range.empty() ? "" : " each " + range);
    case Kind::Object: return "an object";
    case Kind::Array: {
      const std::string items = element->kind == Kind::Object ? "object(s)" : "values, each " + element->expectation();
      return min_items > 0 ? fmt::format("an array of at least {} {}", min_items, items)
                           : "an array of " + (element->kind == Kind::Object ? std::string("objects") : items);
    }
  }
  return "?";
}

std::string pointer_append(const std::string& pointer, const std::string& key) {
  std::string escaped;
  for (char c : key) {
    if (c == '~') escaped += "~0";
    else if (c == '/') escaped += "~1";
    else escaped += c;
  }
  return pointer + "/" + escaped;
}

}  // namespace tetfsi::scene
