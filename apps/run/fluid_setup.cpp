#include "apps/run/fluid_setup.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "apps/run/preflight.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/solid_geometry.hpp"
#include "fluid/io/fluid_output.hpp"
#include "fluid/io/level_set_voxels.hpp"
#include "fluid/io/render_surface.hpp"
#include "fluid/io/voxel_sampling.hpp"
#include "fluid/liquid/level_set.hpp"
#include "mesh/surface_distance.hpp"

namespace tetfsi::run {

fluid::FluidParams fluid_params(const scene::Json& js, spdlog::logger& log) {
  const auto& f = js.at("fluid");
  fluid::FluidParams params;
  params.density = f.at("density").get<double>();
  params.gravity = vec3(js.at("simulation").at("gravity"));
  params.apply_gravity = f.at("apply_gravity").get<bool>();
  if (f.at("type") == "smoke") {
    params.buoyancy.alpha = f.at("buoyancy_alpha").get<double>();
    params.buoyancy.beta = f.at("buoyancy_beta").get<double>();
    params.buoyancy.ambient_temperature = f.at("ambient_temperature").get<double>();
    params.vorticity_epsilon = f.at("vorticity_confinement").get<double>();
  }
  const auto adv = f.at("advection").get<std::string>();
  params.advection = adv == "bfecc"             ? fluid::AdvectionScheme::kBfecc
                     : adv == "semi_lagrangian" ? fluid::AdvectionScheme::kSemiLagrangian
                                                : fluid::AdvectionScheme::kLinear;
  params.particles.transfer = adv == "apic"   ? fluid::ParticleTransfer::kApic
                              : adv == "flip" ? fluid::ParticleTransfer::kFlip
                                              : fluid::ParticleTransfer::kNone;
  params.particles.flip_ratio = f.at("flip_ratio").get<double>();
  params.particles.per_tet = f.at("particles_per_tet").get<int>();
  if (params.particles.enabled())
    log.info("velocity on particles: {}, {} per tet{}", adv, params.particles.per_tet,
             adv == "flip" ? fmt::format(", FLIP share {}", params.particles.flip_ratio) : "");
  params.solver.backend = fluid::parse_solver_backend(f.at("solver").at("type").get<std::string>());
  params.solver.tolerance = f.at("solver").at("tolerance").get<double>();
  params.solver.max_iterations = f.at("solver").at("max_iterations").get<int>();
  params.viscosity = f.at("viscosity").get<double>();
  for (const auto& r : f.at("viscosity_regions"))
    params.viscosity_regions.push_back({{vec3(r.at("lo")), vec3(r.at("hi"))}, r.at("viscosity").get<double>()});
  params.walls = fluid::parse_wall_condition(f.at("walls").get<std::string>());
  // The viscous step's CG stops where the pressure solve does (its increment is what it solves for).
  params.viscous_solver.tolerance = params.solver.tolerance;
  if (params.viscosity > 0) log.info("viscosity {} Pa s, walls {}", params.viscosity, f.at("walls").get<std::string>());
  return params;
}

std::function<Eigen::Vector3d(const Eigen::Vector3d&)> pipe_profile(const fluid::Region& region,
                                                                    const Eigen::Vector3d& peak) {
  const Eigen::Vector3d axis = peak.normalized();
  const Eigen::Vector3d centre = 0.5 * (region.lo + region.hi);
  // R: half the smaller extent of the region across the axis (the axis' dominant coordinate is
  // the one the patch is thin in).
  int along = 0;
  axis.cwiseAbs().maxCoeff(&along);
  double across = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
    if (k != along) across = std::min(across, region.hi[k] - region.lo[k]);
  const double R2 = 0.25 * across * across;
  return [axis, centre, R2, peak](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    const Eigen::Vector3d d = x - centre;
    const double r2 = (d - d.dot(axis) * axis).squaredNorm();
    return std::max(0.0, 1.0 - r2 / R2) * peak;
  };
}

std::vector<fluid::BoundaryPatch> boundary_patches(const scene::Json& js, double ambient) {
  std::vector<fluid::BoundaryPatch> patches;
  const Eigen::Vector3d lo = vec3(js.at("domain").at("lo")), hi = vec3(js.at("domain").at("hi"));
  for (const auto& in : js["domain"].at("inflows")) {
    fluid::BoundaryPatch p;
    p.region = {vec3(in.at("lo")), vec3(in.at("hi"))};
    p.kind = fluid::FaceKind::kInflow;
    p.velocity = vec3(in.at("velocity"));
    if (in.at("profile") == "parabolic") p.velocity_field = pipe_profile(p.region, p.velocity);
    p.smoke = in.at("smoke_density").get<double>();
    const double T = in.at("temperature").get<double>();
    p.temperature = T > 0 ? T : ambient;
    patches.push_back(p);
  }
  for (const auto& wall : js["domain"].at("moving_walls")) {
    fluid::BoundaryPatch p;
    p.kind = fluid::FaceKind::kWall;
    p.region = {vec3(wall.at("lo")), vec3(wall.at("hi"))};
    p.velocity = vec3(wall.at("velocity"));
    patches.push_back(p);
  }
  for (const auto& open : js["domain"].at("open_patches")) {
    fluid::BoundaryPatch p;
    p.kind = fluid::FaceKind::kOpen;
    p.region = {vec3(open.at("lo")), vec3(open.at("hi"))};
    patches.push_back(p);
  }
  // A box face ("x-" ... "z+") as a patch region: the slab of the box within a millionth of its
  // diagonal of that face.
  const double eps = 1e-6 * (hi - lo).norm();
  auto box_face = [&](const std::string& name) {
    const int axis = name[0] - 'x';
    fluid::Region r{lo, hi};
    if (name[1] == '+') r.lo[axis] = hi[axis] - eps;
    else r.hi[axis] = lo[axis] + eps;
    return r;
  };
  for (const auto& face : js["domain"].at("open_faces")) {
    fluid::BoundaryPatch p;
    p.kind = fluid::FaceKind::kOpen;
    p.region = box_face(face.get<std::string>());
    patches.push_back(p);
  }
  for (const auto& face : js["domain"].at("slip_faces")) {
    fluid::BoundaryPatch p;
    p.kind = fluid::FaceKind::kWall;
    p.slip = true;
    p.region = box_face(face.get<std::string>());
    patches.push_back(p);
  }
  return patches;
}

std::vector<TimedSource> timed_sources(const scene::Json& js, spdlog::logger& log) {
  std::vector<TimedSource> out;
  for (std::size_t i = 0; i < js.at("emitters").size(); ++i) {
    const auto& e = js["emitters"][i];
    TimedSource em;
    const auto& shape = e.at("shape");
    if (shape.at("type") == "box") {
      em.source.region = {vec3(shape.at("lo")), vec3(shape.at("hi"))};
    } else {
      const Eigen::Vector3d c = vec3(shape.at("center"));
      const double r = shape.at("radius").get<double>();
      em.source.region = {c.array() - r, c.array() + r};
      log.warn("/emitters/{}: a sphere source acts on the tets whose centroid lies in its bounding box", i);
    }
    em.source.smoke = e.at("smoke_density").get<double>();
    em.source.temperature = e.at("temperature").get<double>();
    em.source.velocity = vec3(e.at("velocity"));
    em.source.set_velocity = em.source.velocity.norm() > 0;
    em.start = e.at("start_time").get<double>();
    if (e.contains("end_time")) em.end = e["end_time"].get<double>();
    out.push_back(em);
  }
  return out;
}

namespace {

/// The solver's mesh with its nodes at `node_positions` and its geometry (centroids, gradients)
/// recomputed, for locating points in the frame's fluid.
fluid::FluidMesh moved_fluid_mesh(const fluid::FluidMesh& mesh, const std::vector<Eigen::Vector3d>& node_positions) {
  fluid::FluidMesh moved = mesh;
  if (node_positions == mesh.nodes) return moved;
  mesh::TetMesh m;
  m.vertices.resize(mesh.mesh_vertex_to_node.size(), Eigen::Vector3d::Zero());
  for (int n = 0; n < mesh.num_nodes(); ++n) m.vertices[mesh.node_to_mesh_vertex[n]] = node_positions[n];
  fluid::update_fluid_mesh_geometry(m, moved);
  return moved;
}

/// The frame's fluid volumes (export.volumes): the node fields of the grid (make_fluid_grid's
/// point data) sampled on the moved mesh, and the liquid's level set from its surface.
void write_fluid_volumes(Output& out, int frame, const fluid::FluidSolver& solver,
                         const std::vector<Eigen::Vector3d>& node_positions, const mesh::SurfaceMesh* surface) {
  const fluid::FluidMesh moved = moved_fluid_mesh(solver.mesh(), node_positions);
  const double h = out.voxel_size(solver.mesh().mean_edge_length());
  const double voxels = fluid::voxel_range(moved, h).count();
  if (!(voxels <= default_max_voxels()))
    throw InputError(fmt::format("/export/voxel_size: {:.4g} m gives {:.3g} voxels over the fluid's bounding box, "
                                 "more than the limit of {:.3g} ({} bytes per voxel, a quarter of this machine's "
                                 "memory): raise /export/voxel_size",
                                 h, voxels, default_max_voxels(), kBytesPerVoxel));
  const auto& f = solver.fields();
  fluid::NodalFields nodal{fluid::average_to_nodes(solver.mesh(), f.smoke),
                           fluid::average_to_nodes(solver.mesh(), f.temperature),
                           fluid::average_to_nodes(solver.mesh(), f.velocity)};
  out.write_volumes("fluid", frame, fluid::sample_voxels(moved, nodal, h), surface);
}

/// The frame's smooth liquid surface (export.liquid_surface "smooth", fluid/io/render_surface.hpp)
/// on the moved mesh, with its vertex velocities.
mesh::SurfaceMesh smooth_liquid_surface(Output& out, const fluid::FluidSolver& solver,
                                        const std::vector<Eigen::Vector3d>& node_positions,
                                        std::vector<Eigen::Vector3d>& velocity) {
  const fluid::FluidMesh moved = moved_fluid_mesh(solver.mesh(), node_positions);
  const Output::SurfaceScale scale = out.liquid_surface_scale(fluid::cut_tet_edge_length(moved, solver.level_set(), 0.1));
  if (scale.voxel_size == 0) return {};  // no tet cut yet: no surface to draw the scale from
  const double voxels = fluid::voxel_range(moved, scale.voxel_size).count();
  if (!(voxels <= default_max_voxels()))
    throw InputError(fmt::format("/export/liquid_surface/voxel_size: {:.4g} m gives {:.3g} voxels over the fluid's "
                                 "bounding box, more than the limit of {:.3g} ({} bytes per voxel, a quarter of this "
                                 "machine's memory): raise /export/liquid_surface/voxel_size",
                                 scale.voxel_size, voxels, default_max_voxels(), kBytesPerVoxel));
  // The volume to keep is the solver's (fluid_volume probe): phi on the nodes moved to the frame's
  // time holds another (fluid_node_positions moves them with the solids, not with the liquid).
  fluid::RenderSurfaceOptions options;
  options.voxel_size = scale.voxel_size;
  options.smoothing = scale.smoothing;
  options.target_volume = solver.liquid().total_volume();
  fluid::RenderSurface s = fluid::render_surface(moved, solver.level_set(), solver.fields().velocity, options);
  if (s.liquid_volume > 0) out.note_surface_volume_error(std::abs(s.enclosed_volume / s.liquid_volume - 1.0));
  velocity = std::move(s.velocity);
  return std::move(s.surface);
}

}  // namespace

void write_fluid_frame(Output& out, int frame, double time, const fluid::FluidSolver& solver,
                       const std::vector<Eigen::Vector3d>& node_positions) {
  if (node_positions.size() != solver.mesh().nodes.size())
    throw std::invalid_argument("write_fluid_frame: " + std::to_string(node_positions.size()) +
                                " node positions for " + std::to_string(solver.mesh().num_nodes()) + " fluid nodes");
  auto grid = fluid::make_fluid_grid(solver.mesh(), solver.fields(), solver.pressure());
  grid.points = node_positions;
  mesh::SurfaceMesh surface;
  if (solver.has_free_surface()) {
    fluid::add_liquid_fields(grid, solver.mesh(), solver.level_set(), solver.liquid().liquid_volume);
    std::vector<Eigen::Vector3d> velocity;
    if (out.smooth_liquid_surface()) {
      surface = smooth_liquid_surface(out, solver, node_positions, velocity);
    } else {
      // The level set's zero set and wet boundary faces on the moved nodes: the surface's vertices
      // are nodes or edge crossings at the same edge fractions (its orientation, read from the
      // solver's mesh, is unchanged by a motion that inverts no tet).
      fluid::FluidMesh moved = solver.mesh();
      moved.nodes = node_positions;
      surface = fluid::liquid_surface(moved, solver.level_set(), solver.fields().velocity, &velocity);
    }
    out.write_surface("liquid", frame, surface, velocity);
  }
  out.write_grid("fluid", frame, time, grid);
  if (out.volumes())
    write_fluid_volumes(out, frame, solver, node_positions, solver.has_free_surface() ? &surface : nullptr);
}

void set_initial_liquid(const scene::Json& scene, fluid::FluidSolver& solver, spdlog::logger& log) {
  const auto& f = scene.at("fluid");
  if (f.at("type") != "liquid" || f.value("fill", "domain") != "regions") return;
  fluid::LiquidOptions liquid;
  liquid.band = 4.0 * solver.mesh().mean_edge_length();
  liquid.bfecc = f.at("level_set_advection") == "bfecc";
  solver.set_liquid(fluid::sample_level_set(solver.mesh(), liquid_region_distance(scene)), liquid);
  log.info("free surface: {:.6g} m^3 of liquid in {} region(s) (level set band {:.4g} m)",
           solver.target_liquid_volume(), f.at("regions").size(), liquid.band);
}

}  // namespace tetfsi::run
