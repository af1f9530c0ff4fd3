#pragma once
/// @file preflight_ignored.hpp
/// Preflight's warnings for values the scene gives and the run does not use as written
/// (preflight.cpp): `tetfsi validate` prints them and `tetfsi run` writes them to run.log and the
/// console, so a value the run ignores or cuts is never dropped without a word.
#include <string>
#include <vector>

#include "apps/scene/scene.hpp"

namespace tetfsi::run {

/// The warnings, each starting with the key's JSON pointer. Only keys the scene file gives
/// (scene.input) are looked at, not defaults:
/// - /simulation/cfl with /simulation/dt given, or in a runner without a CFL step (all but the
///   fluid and coupled runners);
/// - /simulation/dt longer than the frame interval 1 / frame_rate (the steps are cut to land on
///   every frame), unless a static analysis takes load steps instead;
/// - /fluid/regions without `fill: regions`;
/// - /obstacles in the fluid runner (it moves no solid);
/// - /mesh/edge_length in a scene without a meshed fluid that is longer than every tet-meshed solid
///   (`largest_meshed_solid`: the largest bounding-box edge of those solids [m], 0 if none: then
///   nothing is meshed at that length).
std::vector<std::string> ignored_value_warnings(const scene::Scene& scene, const std::string& runner,
                                                bool meshes_fluid, double largest_meshed_solid);

}  // namespace tetfsi::run
