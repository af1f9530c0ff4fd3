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
/// Check that object[end] > object[start] when both are present (a time window).
Check start_before_end(std::string start = "start_time", std::string end = "end_time");
/// Young's modulus E [Pa], required, 0 < E <= kMaxYoungsModulus.
Field youngs_modulus(std::string doc);
/// Largest Young's modulus a scene may give [Pa]: ten times diamond's 1.05e12 Pa, the stiffest bulk
/// material. Beyond it the stiffness matrix's entries (E / h, up to E * 1e300 for a tiny mesh) leave
/// the range CHOLMOD factorizes (it warned four times and the run failed naming no key at 1e300).
constexpr double kMaxYoungsModulus = 1e13;

}  // namespace tetfsi::scene::blocks
