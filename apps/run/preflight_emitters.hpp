#pragma once
/// @file preflight_emitters.hpp
/// Preflight's check of /emitters (preflight.cpp): an emitter outside the fluid's domain does
/// nothing and one that reaches outside acts only inside; both are warned about, not refused.
#include <functional>
#include <string>
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// The warnings about the scene's /emitters: none without emitters; one if the scene meshes no fluid
/// domain (`meshes_fluid` false); else one per emitter shape outside or reaching outside the domain.
/// `check_magnitude(pointer, m)` is called with each shape's largest coordinate magnitude [m].
std::vector<std::string> emitter_warnings(const scene::Json& js, bool meshes_fluid,
                                          const std::function<void(const std::string&, double)>& check_magnitude);

}  // namespace tetfsi::run
