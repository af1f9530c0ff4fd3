#pragma once
/// @file fluid_setup.hpp
/// The fluid's settings from the resolved scene, shared by the runners that have a tet-mesh fluid
/// (fluid_runner.cpp, coupled_runner.cpp): solver parameters, boundary patches of the domain box,
/// and emitters with their switch-on and switch-off times.
#include <functional>
#include <limits>
#include <vector>

#include <spdlog/logger.h>

#include "apps/run/output.hpp"
#include "apps/scene/scene.hpp"
#include "fluid/fluid_solver.hpp"

namespace tetfsi::run {

/// FluidParams from /fluid and /simulation (density, gravity, buoyancy, vorticity confinement,
/// advection scheme, pressure solver, viscosity and wall condition).
fluid::FluidParams fluid_params(const scene::Json& scene, spdlog::logger& log);

/// The pipe (Poiseuille) inflow profile of /domain/inflows/i/profile "parabolic":
/// u(x) = u_peak (1 − r²/R²) for r < R, else 0, with r the distance of x from the line through the
/// centre of `region` along u_peak and R half the smaller extent of `region` across it.
std::function<Eigen::Vector3d(const Eigen::Vector3d&)> pipe_profile(const fluid::Region& region,
                                                                    const Eigen::Vector3d& peak);

/// Inflow patches (/domain/inflows, uniform or parabolic), open patches (/domain/open_patches)
/// and open faces (/domain/open_faces) of the container, first match first; the other faces are
/// walls. An inflow without a temperature gets `ambient_temperature` [K].
std::vector<fluid::BoundaryPatch> boundary_patches(const scene::Json& scene, double ambient_temperature);

/// An emitter (/emitters/i): a source volume active for start <= t < end [s].
struct TimedSource {
  fluid::SourceVolume source;
  double start = 0, end = std::numeric_limits<double>::infinity();
  bool active(double t) const { return t >= start - 1e-12 && t < end; }
};

/// The scene's emitters; a sphere source acts over its bounding box (logged).
std::vector<TimedSource> timed_sources(const scene::Json& scene, spdlog::logger& log);

/// With /fluid/fill "regions": makes `solver` (initialised on its first mesh) a liquid with a free
/// surface whose level set is the signed distance to the union of /fluid/regions (level set band:
/// 4 mean edge lengths). Other scenes: nothing. @throws std::invalid_argument if the regions hold
/// no liquid on the mesh
void set_initial_liquid(const scene::Json& scene, fluid::FluidSolver& solver, spdlog::logger& log);

/// Signed distance [m] to the free surface of the union of the scene's /fluid/regions (negative
/// inside; `below` is measured along -/simulation/gravity): the minimum of the shapes' distances,
/// exact outside every shape. A box region's faces that lie on the walls of /domain (within 1e-9 of
/// its diagonal) or beyond them are not surfaces: the box is taken to go on through the wall, so a
/// column standing on the floor has phi = -(depth) at the floor's nodes, not 0 (fluid/README.md,
/// "Liquids").
std::function<double(const Eigen::Vector3d&)> liquid_region_distance(const scene::Json& scene);

/// Signed distance [m] to region /fluid/regions/i of `scene` alone, as liquid_region_distance takes
/// it (a box's faces on the walls moved out; a `mesh` region's file read and placed).
/// @throws InputError for a `mesh` region's unreadable or broken file
std::function<double(const Eigen::Vector3d&)> liquid_region_shape(const scene::Json& scene, std::size_t i);

/// Writes the fluid's frame: the grid "fluid" (with the level set and liquid fractions of a free
/// surface), for a free surface the closed liquid surface "liquid" with vertex velocities, and
/// with export.volumes the volume file "fluid" (node fields at the voxel centres; the liquid
/// surface's level set). @throws InputError naming /export/voxel_size if the voxels over the
/// fluid's bounding box exceed default_max_voxels()
/// Both are drawn with the fluid nodes at `node_positions` (solver.mesh().nodes order), the
/// positions at `time` (coupled runs: coupling::CoupledStepper::fluid_node_positions, so that the
/// fluid's interface vertices are the solids' vertices of the same frame); the fields are the
/// solver's. @throws std::invalid_argument if node_positions has another size than the mesh
void write_fluid_frame(Output& out, int frame, double time, const fluid::FluidSolver& solver,
                       const std::vector<Eigen::Vector3d>& node_positions);

}  // namespace tetfsi::run
