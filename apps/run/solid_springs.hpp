#pragma once
/// @file solid_springs.hpp
/// The scene's `solids[i].springs`: linear springs tying a region of a tet solid to a fixed
/// anchor, shared by the runners that integrate tet solids (coupled, solid).
///
/// A spring selects the solid's nodes whose rest position lies in `region` (a box) or the node
/// nearest to `point`, and spreads its total stiffness k [N/m] evenly over them: each of the n
/// nodes gets k/n towards `anchor` (one point for all, or each node's own rest position when
/// `anchor` is omitted). A rigid translation Δ of the region is then resisted by the force −k Δ,
/// and the spring energy Σ ½ (k/n) |x_a − anchor_a|² enters the total energy.
#include <string>

#include <spdlog/logger.h>

#include "apps/scene/scene.hpp"
#include "solid/integrator/newmark.hpp"

namespace tetfsi::run {

/// Adds the springs of one resolved solid block to its integrator.
/// @param solid        the resolved /solids/i object
/// @param solid_index  i, for the JSON pointer in messages
/// @param solid_name   the solid's name, for messages
/// @throws InputError naming the solid and the spring (pointer and name) if a region holds no node
/// @returns the number of springs added (one per selected node)
int add_scene_springs(solid::NewmarkIntegrator& integrator, const scene::Json& solid, int solid_index,
                      const std::string& solid_name, spdlog::logger& log);

}  // namespace tetfsi::run
