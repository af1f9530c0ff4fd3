#pragma once
/// @file preflight.hpp
/// Every check of a scene that needs no meshing, shared by `tetfsi validate` and `tetfsi run`
/// (so both give the same verdict): surface files read and checked (closed, manifold, oriented,
/// not self-intersecting), coordinates within the range the mesher resolves, solids inside the
/// domain and free of overlaps, a runner that can run the scene and its probes, and resource
/// guards (tet count and memory, number of steps, output size) estimated before anything is
/// meshed or written.
#include <optional>
#include <string>
#include <vector>

#include "apps/scene/scene.hpp"

namespace tetfsi::run {

/// Largest |coordinate| [m] of the domain, the placed solids, inflows and emitters: beyond it
/// double precision no longer resolves mesh sizes of a millimetre (CGAL Mesh_3 failed on a solid
/// translated by 1e13 m and crashed on 1e15 m and on a domain corner at -1e300 m).
constexpr double kMaxCoordinate = 1e6;
/// Largest ratio of a coordinate to the finest edge length near it: the mesher's constructions
/// need about 1e-9 relative precision left over the size (a double has 1e-16).
constexpr double kMaxCoordinateOverEdge = 1e8;
/// Estimated peak memory per tet [bytes] (mesher, model and solver; measured at about 2 KB per
/// tet on the data/scenes runs, doubled for the CGAL refinement peak).
constexpr double kBytesPerTet = 4096;
/// Bytes one tet adds to a .vtu frame (positions, connectivity, fields; measured about 130
/// uncompressed, export.compression "none"). zlib frames take 0.33-0.47 of that on the flagship
/// scenes, so with compression the estimate is an upper bound.
constexpr double kVtuBytesPerTet = 150;

/// Peak memory per voxel of a volume frame [bytes]: samples (index, 5 floats) while sampling, and
/// the OpenVDB trees (4 + 4 + 12 bytes of values, leaf masks) with the file's bytes while writing.
constexpr double kBytesPerVoxel = 96;
/// Bytes one voxel inside the fluid adds to a .vdb frame, at most (uncompressed values of
/// `density`, `temperature`, `velocity`; zlib and pruning write less).
constexpr double kVdbBytesPerVoxel = 20;

/// The voxel limit of export.volumes: a quarter of the physical memory / kBytesPerVoxel.
double default_max_voxels();

/// Peak memory per particle of fluid.advection "apic" / "flip" [bytes]: position, velocity, APIC's
/// 3x3 gradient and tet (124 bytes), and the step's copies while sorting, reseeding and transferring.
constexpr double kBytesPerParticle = 320;

/// The particle limit: a quarter of the physical memory / kBytesPerParticle.
double default_max_particles();

struct PreflightOptions {
  std::optional<double> max_tets;  ///< --max-tets; default: half the machine's memory / kBytesPerTet
  /// MPI processes of the run (parallel::num_processes(); 1 without mpirun): passed in, so that
  /// the checks link no MPI code (`tetfsi validate` runs without it, apps/cli/front.cpp).
  int processes = 1;
};

/// What the checks estimated (for run.log and messages).
struct PreflightReport {
  std::string runner;           ///< the runner that will run the scene
  double tets = 0;              ///< estimated tet (or hex cell) count of the mesh
  double max_tets = 0;          ///< the limit applied
  double steps = 0;             ///< estimated number of steps (lower bound when the step follows the CFL)
  double particles = 0;         ///< particles carried at most (fluid.advection "apic", "flip")
  double frames = 0;            ///< frames written
  double output_bytes = 0;      ///< estimated size of the output folder [bytes]
  std::vector<std::string> warnings;
};

/// "12.3 kB", "4.56 MB", "7.89 GB" (for messages).
std::string format_bytes(double bytes);

/// The default tet limit: half the physical memory divided by kBytesPerTet.
double default_max_tets();

/// Estimated tets of one closed solid of volume V and area A meshed alone at edge length h
/// (see estimate_tets in preflight.cpp): 6 sqrt(2) (V / h_s^3 + A / h_s^2), h_s = min(h, 3V/A).
double estimate_solid_tets(double volume, double area, double edge_length);

/// Runs every check. @throws scene::SceneError listing every problem with its JSON pointer
PreflightReport preflight(const scene::Scene& scene, const PreflightOptions& options = {});

}  // namespace tetfsi::run
