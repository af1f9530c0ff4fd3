#pragma once
/// @file preflight_regions.hpp
/// Preflight's check of the boxes that select a solid's nodes (preflight.cpp).
#include <vector>

#include "apps/run/preflight_contact.hpp"
#include "apps/run/preflight_container.hpp"
#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// A boundary-condition or fixed-region box that misses the solid's bounding box, or lies wholly
/// outside the solid, selects no node: the run would stop on it after meshing, so validate says so
/// too (a hex8 solid's fixed regions are checked on its mesh: empty_hex_regions). `boxes` and
/// `solids` follow /solids (a box not `ok` is skipped). Each issue with its JSON pointer.
std::vector<scene::Issue> empty_region_issues(const scene::Json& js, const std::vector<PlacedBox>& boxes,
                                              const std::vector<ContainedSolid>& solids);

}  // namespace tetfsi::run
