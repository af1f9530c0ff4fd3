#pragma once
/// @file blocks.hpp
/// The scene file's blocks, one short file each; scene_schema.cpp assembles them.
#include <string>

#include "apps/scene/schema.hpp"

namespace tetfsi::scene::blocks {

Field simulation();
Field domain();
Field mesh();
Field fluid();
Field solids();
Field coupling();
Field obstacles();
Field emitters();
Field probes();
Field output();
Field mpm();

// Shared pieces.
/// Check that object[lo] < object[hi] componentwise.
Check lo_below_hi(std::string lo = "lo", std::string hi = "hi");
/// Check that the Vector member `key` is not the zero vector.
Check nonzero(std::string key);
/// An axis-aligned box {lo, hi} [m], both required, lo < hi.
Field box(std::string key, std::string doc);

}  // namespace tetfsi::scene::blocks
