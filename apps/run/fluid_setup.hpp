#pragma once
/// @file fluid_setup.hpp
/// The fluid's settings from the resolved scene, shared by the runners that have a tet-mesh fluid
/// (fluid_runner.cpp, coupled_runner.cpp): solver parameters, boundary patches of the domain box,
/// and emitters with their switch-on and switch-off times.
#include <limits>
#include <vector>

#include <spdlog/logger.h>

#include "apps/scene/scene.hpp"
#include "fluid/fluid_solver.hpp"

namespace tetfsi::run {

/// FluidParams from /fluid and /simulation (density, gravity, buoyancy, vorticity confinement,
/// advection scheme, pressure solver). Logs that /fluid/viscosity is unused (inviscid model).
fluid::FluidParams fluid_params(const scene::Json& scene, spdlog::logger& log);

/// Inflow patches (/domain/inflows) and open faces (/domain/open_faces) of the domain box; the
/// other faces are walls. An inflow without a temperature gets `ambient_temperature` [K].
std::vector<fluid::BoundaryPatch> boundary_patches(const scene::Json& scene, double ambient_temperature);

/// An emitter (/emitters/i): a source volume active for start <= t < end [s].
struct TimedSource {
  fluid::SourceVolume source;
  double start = 0, end = std::numeric_limits<double>::infinity();
  bool active(double t) const { return t >= start - 1e-12 && t < end; }
};

/// The scene's emitters; a sphere source acts over its bounding box (logged).
std::vector<TimedSource> timed_sources(const scene::Json& scene, spdlog::logger& log);

}  // namespace tetfsi::run
