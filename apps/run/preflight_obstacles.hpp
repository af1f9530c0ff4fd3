#pragma once
/// @file preflight_obstacles.hpp
/// Preflight's check of /obstacles against the placed solids (preflight.cpp): a solid that starts
/// inside an obstacle is refused before anything is meshed. The obstacles act on the solid's nodes
/// (solid/contact), so such a solid was pushed out in its first step and stopped on inverted tets,
/// naming neither the obstacle nor the placement.
#include <vector>

#include <Eigen/Core>

#include "apps/run/preflight_container.hpp"
#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// For each deforming solid (`/motion` none, not a static analysis, which meets no obstacle) of a runner that applies /obstacles (solid, hex,
/// coupled): a surface vertex behind a plane (its normal points to the free side) or inside a box
/// by more than 1e-6 of the solid's size is an issue at /solids/i/placement naming the obstacle.
/// `solids` follow /solids (a null surface is not checked).
/// Whether the box [lo, hi] lies wholly outside the solid bounded by the closed, outward-oriented
/// surface `s`: no triangle's bounding box meets the box (so the surface does not cross it) and the
/// box's centre has winding number 0 (a solid-angle sum, Van Oosterom & Strackee 1983). The solid's
/// mesh then has no node in the box (Mesh_3 puts its boundary nodes on the surface).
bool box_outside_solid(const mesh::SurfaceMesh& s, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

std::vector<scene::Issue> obstacle_issues(const scene::Json& js, const std::string& runner,
                                          const std::vector<ContainedSolid>& solids);

}  // namespace tetfsi::run
