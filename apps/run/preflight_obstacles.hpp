#pragma once
/// @file preflight_obstacles.hpp
/// Preflight's check of /obstacles against the placed solids (preflight.cpp): a solid that starts
/// inside an obstacle is refused before anything is meshed. The obstacles act on the solid's nodes
/// (solid/contact), so such a solid was pushed out in its first step and stopped on inverted tets,
/// naming neither the obstacle nor the placement.
#include <vector>

#include "apps/run/preflight_container.hpp"
#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// For each deforming solid (`/motion` none, not a static analysis, which meets no obstacle) of a runner that applies /obstacles (solid, hex,
/// coupled): a surface vertex behind a plane (its normal points to the free side) or inside a box
/// by more than 1e-6 of the solid's size is an issue at /solids/i/placement naming the obstacle.
/// `solids` follow /solids (a null surface is not checked).
std::vector<scene::Issue> obstacle_issues(const scene::Json& js, const std::string& runner,
                                          const std::vector<ContainedSolid>& solids);

}  // namespace tetfsi::run
