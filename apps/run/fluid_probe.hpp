#pragma once
/// @file fluid_probe.hpp
/// The `fluid_point` probe, shared by the fluid and coupled runners: one fluid quantity at a point.
#include <Eigen/Core>

#include "apps/scene/scene.hpp"
#include "fluid/fluid_solver.hpp"

namespace tetfsi::run {

/// Value of the resolved /probes/i (kind fluid_point) at its `point`: pressure interpolated
/// linearly in the tet (nodal pressure), smoke, temperature, speed or a velocity component of
/// the tet (per-tet values). NaN if the point is outside the fluid (in a solid or outside the
/// domain); the driver writes that as an empty probes.csv cell.
double fluid_point_value(const fluid::FluidSolver& fluid, const scene::Json& probe);

}  // namespace tetfsi::run
