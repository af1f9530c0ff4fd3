#pragma once
/// @file preflight_liquid.hpp
/// Preflight's checks of a free-surface liquid's regions (/fluid/regions with /fluid/fill
/// "regions"; preflight.cpp), so that `validate` refuses a liquid that the run would start without.
#include <vector>

#include "apps/run/preflight_container.hpp"
#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// Every region must hold liquid: some of it inside the domain box, inside the container (a
/// sphere, cylinder or mesh /domain/container) and outside every solid. Judged on a lattice of
/// 24^3 points over the part of the region's bounding box inside the domain box (a box region
/// fills its box, so it is never missed; a shape thinner than 1/24 of its own extent could be).
/// Each issue names /fluid/regions/i; `solids` follow /solids (a solid whose surface could not be
/// read is not checked). (An empty list of regions is the schema's to refuse.)
std::vector<scene::Issue> liquid_region_issues(const scene::Json& js, const std::vector<ContainedSolid>& solids);

}  // namespace tetfsi::run
