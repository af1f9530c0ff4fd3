#pragma once
/// @file vdb_surface.hpp
/// A closed triangle mesh of the liquid from its smoothed level set on voxels (surface_voxels.hpp),
/// built with OpenVDB (Museth 2013, "VDB: high-resolution sparse volumes with dynamic topology",
/// ACM TOG 32(3)). This interface holds no OpenVDB type. With phi_s the smoothed level set and D
/// the signed distance to the fluid's walls (negative in the fluid):
///
/// 1. The liquid is {phi_s < delta} within the fluid: on the voxels,
///       psi = max(phi_s - delta, D)
///    (the intersection of the two level sets). The smoothing never touched D, so the liquid ends
///    at a wall or a solid exactly, with a sharp edge where its surface meets it.
/// 2. The zero set of psi: openvdb::tools::volumeToMesh, adaptivity 0 (one vertex per voxel cell
///    the surface crosses, at the mean of the edge crossings: closed and watertight). A vertex whose
///    cell a wall takes part in is moved to the minimiser of its quadric error (sharp_edges.cpp,
///    vdb_fields.hpp), so that edges along walls and corners are not bevelled; the others to the
///    mean of the exact crossings of phi_s - delta. Quads are split along their shorter diagonal;
///    outward orientation.
/// 3. Volume: delta is the one constant for which the enclosed volume equals the target (secant
///    steps, the first a Newton step on the surface area off the walls), as the solver's
///    restore_volume does for phi: smoothing shrinks convex parts and swells concave ones.
#include "fluid/io/surface_voxels.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::fluid {

struct VdbSurfaceOptions {
  double target_volume = -1;       ///< volume the mesh must enclose [m^3]; < 0: delta = 0
  double volume_tolerance = 1e-4;  ///< relative, on the enclosed volume
  int max_meshings = 8;            ///< secant steps (each meshes the zero set once)
  double max_shift = 1e300;        ///< largest |delta| [m] (and half the band): where the voxels hold phi_s
};

struct VdbSurface {
  mesh::SurfaceMesh surface;   ///< closed, outward-oriented [m]
  double enclosed_volume = 0;  ///< of `surface` [m^3]
  double iso_shift = 0;        ///< delta [m]
  int meshings = 0;
};

/// Steps 1 to 3 on `voxels` and the boundary triangles they were made with. An empty mesh if no
/// voxel in the fluid holds liquid.
VdbSurface mesh_liquid_voxels(const SurfaceVoxels& voxels, const BoundaryTriangles& walls,
                              const VdbSurfaceOptions& options);

}  // namespace tetfsi::fluid
