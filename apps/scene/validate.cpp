#include "apps/scene/validate.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

namespace tetfsi::scene {
namespace fs = std::filesystem;
namespace {

/// Short description of a JSON value for "got ..." in messages.
std::string describe(const Json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return fmt::format("an array of {} element(s)", v.size());
  if (v.is_null()) return "null";
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

bool has_required_member(const Field& f) {
  return std::any_of(f.members.begin(), f.members.end(), [](const Field& m) { return m.required; });
}

/// Largest magnitude of an Integer key: every integer of the scene is read as a C++ int.
constexpr double kMaxInteger = 2147483647.0;

bool in_range(const Field& f, double x) {
  return (!f.gt || x > *f.gt) && (!f.ge || x >= *f.ge) && (!f.lt || x < *f.lt) &&
         (!f.le || x <= *f.le);
}

class Validator {
 public:
  Validator(fs::path base, std::vector<Issue>& issues) : base_(std::move(base)), issues_(issues) {}

  Json value(const Json& v, const Field& f, const std::string& ptr) {
    switch (f.kind) {
      case Kind::Number:
      case Kind::Integer: {
        const bool ok_type = f.kind == Kind::Number
                                 ? v.is_number()
                                 : (v.is_number_integer() ||
                                    (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>()));
        if (!ok_type || !in_range(f, v.get<double>())) return bad(ptr, f, v);
        if (f.kind == Kind::Integer && !(std::fabs(v.get<double>()) <= kMaxInteger)) {
          issues_.push_back({ptr, fmt::format("expected {}, got {}: integers are limited to +-{} here",
                                              f.expectation(), describe(v), kMaxInteger)});
          return Json();
        }
        return f.kind == Kind::Integer ? Json(v.get<long long>()) : v;
      }
      case Kind::Bool:
        if (!v.is_boolean()) return bad(ptr, f, v);
        return v;
      case Kind::String:
        if (!v.is_string()) return bad(ptr, f, v);
        return v;
      case Kind::Enum: {
        if (!v.is_string()) return bad(ptr, f, v);
        const auto s = v.get<std::string>();
        if (std::find(f.choices.begin(), f.choices.end(), s) == f.choices.end()) {
          const std::string hint = closest_match(s, f.choices);
          issues_.push_back({ptr, fmt::format("expected {}, got \"{}\"{}", f.expectation(), s,
                                              hint.empty() ? "" : "; did you mean \"" + hint + "\"?")});
          return Json();
        }
        return v;
      }
      case Kind::EnumSet: {
        if (!v.is_array() || (v.empty() && !f.empty_set_allowed())) return bad(ptr, f, v);
        std::vector<std::string> seen;
        for (std::size_t i = 0; i < v.size(); ++i) {
          const std::string iptr = ptr + "/" + std::to_string(i);
          const bool known = v[i].is_string() &&
                             std::find(f.choices.begin(), f.choices.end(), v[i].get<std::string>()) != f.choices.end();
          if (!known) {
            std::string list;
            for (const auto& c : f.choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
            issues_.push_back({iptr, fmt::format("expected one of {}, got {}", list, describe(v[i]))});
            return Json();
          }
          const auto s = v[i].get<std::string>();
          if (std::find(seen.begin(), seen.end(), s) != seen.end()) {
            issues_.push_back({iptr, fmt::format("expected {}, got \"{}\" twice", f.expectation(), s)});
            return Json();
          }
          seen.push_back(s);
        }
        return v;
      }
      case Kind::File: {
        if (!v.is_string() || v.get<std::string>().empty()) return bad(ptr, f, v);
        fs::path p = v.get<std::string>();
        if (p.is_relative()) p = base_ / p;
        p = p.lexically_normal();
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) {
          issues_.push_back({ptr, fmt::format("file not found: {} (relative paths are resolved from "
                                              "the scene file's folder)", p.string())});
          return Json();
        }
        return p.string();
      }
      case Kind::Vector: {
        if (!v.is_array() || static_cast<int>(v.size()) != f.length) return bad(ptr, f, v);
        for (const auto& x : v)
          if (!x.is_number() || !in_range(f, x.get<double>())) return bad(ptr, f, v);
        return v;
      }
      case Kind::Object: return object(v, f, ptr);
      case Kind::Array: {
        if (!v.is_array() || static_cast<int>(v.size()) < f.min_items) return bad(ptr, f, v);
        Json out = Json::array();
        for (std::size_t i = 0; i < v.size(); ++i)
          out.push_back(value(v[i], *f.element, ptr + "/" + std::to_string(i)));
        return out;
      }
    }
    return Json();
  }

 private:
  Json bad(const std::string& ptr, const Field& f, const Json& v) {
    issues_.push_back({ptr, fmt::format("expected {}{}, got {}", f.expectation(),
                                        f.unit.empty() ? "" : " [" + f.unit + "]", describe(v))});
    return Json();
  }

  Json object(const Json& v, const Field& f, const std::string& ptr) {
    if (!v.is_object()) return bad(ptr, f, v);
    const std::size_t issues_before = issues_.size();
    std::vector<const Field*> members;
    for (const auto& m : f.members) members.push_back(&m);
    bool tag_known = f.tag.empty();
    if (!f.tag.empty()) {
      auto it = v.find(f.tag);
      if (it != v.end() && it->is_string()) {
        auto var = f.variants.find(it->get<std::string>());
        if (var != f.variants.end()) {
          tag_known = true;
          for (const auto& m : var->second) members.push_back(&m);
        }
      }
    }
    std::vector<std::string> allowed;
    for (const auto* m : members) allowed.push_back(m->key);

    Json out = Json::object();
    for (const auto& [key, val] : v.items()) {
      auto m = std::find_if(members.begin(), members.end(), [&k = key](const Field* x) { return x->key == k; });
      if (m != members.end()) continue;
      std::vector<std::string> owners;  // the variants that have this key
      for (const auto& [name, extra] : f.variants)
        for (const auto& e : extra)
          if (e.key == key) owners.push_back(name);
      std::string owner;  // "a", "a" or "b", "a", "b" or "c"
      for (std::size_t i = 0; i < owners.size(); ++i)
        owner += (i == 0 ? "\"" : i + 1 == owners.size() ? " or \"" : ", \"") + owners[i] + "\"";
      if (!tag_known && !owner.empty()) continue;  // reported through the tag instead
      std::string msg = fmt::format("unknown key \"{}\"", key.size() <= 64 ? key : key.substr(0, 64) + "...");
      if (!owner.empty()) {
        msg += fmt::format(" for {} \"{}\" (it belongs to {} {})", f.tag, v.at(f.tag).get<std::string>(), f.tag,
                           owner);
      } else if (auto hint = key.size() <= 64 ? closest_match(key, allowed) : ""; !hint.empty()) {
        msg += fmt::format("; did you mean \"{}\"?", hint);
      } else {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        msg += "; allowed keys here: " + list;
      }
      issues_.push_back({pointer_append(ptr, key), msg});
    }
    for (const auto* m : members) {
      const std::string mptr = pointer_append(ptr, m->key);
      auto it = v.find(m->key);
      if (it != v.end()) {
        out[m->key] = value(*it, *m, mptr);
      } else if (m->required) {
        issues_.push_back({mptr, fmt::format("missing required key: expected {}{}", m->expectation(),
                                             m->unit.empty() ? "" : " [" + m->unit + "]")});
      } else if (!m->default_value.is_null()) {
        out[m->key] = m->kind == Kind::Object ? object(Json::object(), *m, mptr) : m->default_value;
      } else if (m->kind == Kind::Object && !has_required_member(*m)) {
        out[m->key] = object(Json::object(), *m, mptr);  // nested defaults
      }
    }
    if (issues_.size() == issues_before)
      for (const auto& check : f.checks) check(out, ptr, issues_);
    return out;
  }

  fs::path base_;
  std::vector<Issue>& issues_;
};

}  // namespace

int edit_distance(const std::string& a, const std::string& b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = 1 << 30;
  for (const auto& c : candidates) {
    const int d = edit_distance(word, c);
    if (d < best_d) { best_d = d; best = c; }
  }
  const int limit = std::max<int>(2, static_cast<int>(word.size()) / 3);
  return best_d <= limit ? best : "";
}

Json validate(const Json& input, const Field& schema, const fs::path& base_dir,
              std::vector<Issue>& issues) {
  return Validator(base_dir, issues).value(input, schema, "");
}

}  // namespace tetfsi::scene
