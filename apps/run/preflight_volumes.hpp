#pragma once
/// @file preflight_volumes.hpp
/// Preflight's check of the volume frames of export.volumes "vdb" (preflight.cpp).
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// Voxels of one volume frame over the domain box at export.voxel_size or, absent, at
/// `default_voxel_size` (preflight passes half the finest edge length: the mean edge the run's
/// default is half of is longer, so this is an upper bound), counted as fluid::voxel_range does at
/// most; above default_max_voxels() an issue naming /export/voxel_size joins `issues`. 0 without a
/// domain (the run checks the fluid mesh at its first frame).
double volume_voxels(const scene::Json& js, double default_voxel_size, std::vector<scene::Issue>& issues);

/// The same for the smooth liquid surface (export.liquid_surface) when the scene sets its
/// voxel_size or smoothing (its voxel size is then known): the voxels over the domain box, with an
/// issue naming /export/liquid_surface/voxel_size (or smoothing) above default_max_voxels().
void liquid_surface_voxels(const scene::Json& js, std::vector<scene::Issue>& issues);

}  // namespace tetfsi::run
