#pragma once
/// @file preflight_particles.hpp
/// Preflight's check of the particles of fluid.advection "apic" or "flip" (preflight.cpp).
#include <vector>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

/// Particles a run of the scene carries at most: fluid.particles_per_tet times `fluid_tets` (the
/// estimated tets: every fluid tet full of liquid, an upper bound), 0 when the velocity is not on
/// particles; above default_max_particles() an issue naming /fluid/particles_per_tet joins `issues`.
double particle_count(const scene::Json& js, double fluid_tets, std::vector<scene::Issue>& issues);

}  // namespace tetfsi::run
