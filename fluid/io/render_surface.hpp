#pragma once
/// @file render_surface.hpp
/// The liquid surface for renderers, smooth at a length the user sets: the nodal level set phi
/// sampled on voxels of size h (level_set_voxels.hpp), filtered with a Gaussian of standard
/// deviation sigma, cut off at the fluid's walls and solids, meshed and given back the liquid's
/// volume by one shift of the iso-value (vdb_surface.hpp), with the fluid's velocity at each vertex.
/// The marching-tets surface (level_set.hpp, liquid_surface) shows every tet: its facets meet at
/// the angles of the P1 level set's kinks; this one bends by a small angle from one triangle to
/// the next wherever the liquid's own shape is smooth at the scale sigma.
#include <Eigen/Core>
#include <vector>

#include "fluid/operators/fluid_mesh.hpp"
#include "fluid/operators/p1_operators.hpp"
#include "mesh/surface_mesh.hpp"

namespace tetfsi::fluid {

struct RenderSurfaceOptions {
  double voxel_size = 0;  ///< h [m], > 0
  double smoothing = 0;   ///< sigma [m], >= 0 (0: the level set resampled, not filtered)
  double volume_tolerance = 1e-4;  ///< relative error of the enclosed volume the iso shift aims at
  /// The volume the surface must enclose [m^3]; < 0: that of phi on `mesh`. A coupled run passes the
  /// solver's (its mesh at x^n), since the frame draws phi on the nodes moved to x^{n+1}, where the
  /// same nodal phi holds another volume (up to 4% in bowl_drop_ci's impact).
  double target_volume = -1;
};

struct RenderSurface {
  mesh::SurfaceMesh surface;               ///< closed, outward-oriented [m]
  std::vector<Eigen::Vector3d> velocity;   ///< per vertex [m/s]
  double liquid_volume = 0;    ///< the target: options.target_volume, or sum_t |Omega_t| of phi on `mesh` [m^3]
  double enclosed_volume = 0;  ///< of `surface` [m^3]
  double iso_shift = 0;        ///< the constant added to the iso-value to keep the volume [m]
};

/// The smooth surface of the liquid {phi < 0} on `mesh` (node positions and geometry of the frame).
/// Vertex velocities: the node-averaged velocity (average_to_nodes of `velocity`, as the .vtu
/// point data) interpolated linearly in the tet holding the vertex, as ParaView draws it; for a
/// vertex outside the fluid (on a wall or a solid, by round-off or the mesher's crossings), at the
/// point half a voxel inside the surface along the vertex normal, and if that is outside too, the
/// mean of its neighbours' (zero for a vertex with none found within four rings).
/// @throws std::invalid_argument if voxel_size <= 0, smoothing < 0 or phi does not match the mesh
RenderSurface render_surface(const FluidMesh& mesh, const Eigen::VectorXd& phi, const TetVectors& velocity,
                             const RenderSurfaceOptions& options);

}  // namespace tetfsi::fluid
