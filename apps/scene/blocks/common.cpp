#include <fmt/format.h>

#include "apps/scene/blocks/blocks.hpp"

namespace tetfsi::scene::blocks {

Check lo_below_hi(std::string lo, std::string hi) {
  return [lo, hi](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (!o.contains(lo) || !o.contains(hi)) return;
    for (int i = 0; i < 3; ++i) {
      if (!(o[lo][i].get<double>() < o[hi][i].get<double>())) {
        issues.push_back({pointer_append(ptr, hi),
                          fmt::format("expected {} > {} in every coordinate, got {} = {} and {} = {}",
                                      hi, lo, lo, o[lo].dump(), hi, o[hi].dump())});
        return;
      }
    }
  };
}

Check start_before_end(std::string start, std::string end) {
  return [start, end](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (!o.contains(start) || !o.contains(end) || o[end].get<double>() > o[start].get<double>()) return;
    issues.push_back({pointer_append(ptr, end), fmt::format("expected {} > {} ({} s): the source would never be on, got "
                                                            "{} s", end, start, o[start].get<double>(),
                                                            o[end].get<double>())});
  };
}

Field youngs_modulus(std::string doc) {
  return Field::number("youngs_modulus", "Pa", std::move(doc) + " The bound is ten times diamond's 1.05e12 Pa.")
      .req().greater(0).at_most(kMaxYoungsModulus);
}

Check nonzero(std::string key) {
  return [key](const Json& o, const std::string& ptr, std::vector<Issue>& issues) {
    if (!o.contains(key)) return;
    double n2 = 0;
    for (const auto& x : o[key]) n2 += x.get<double>() * x.get<double>();
    if (n2 == 0) issues.push_back({pointer_append(ptr, key), "expected a non-zero vector, got [0,0,0]"});
  };
}

Field box(std::string key, std::string doc) {
  return Field::object(std::move(key), std::move(doc),
                       {Field::vector("lo", 3, "m", "Lower corner.").req(),
                        Field::vector("hi", 3, "m", "Upper corner (> lo in every coordinate).").req()})
      .check(lo_below_hi());
}

}  // namespace tetfsi::scene::blocks
