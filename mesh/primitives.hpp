#pragma once
/// @file primitives.hpp
/// Closed, outward-oriented triangle surfaces made without files: box, sphere, cylinder, bowl, sheet.
/// All are centred at the origin; place them with apply_placement() (surface_import.hpp).
#include <Eigen/Core>

#include "mesh/surface_mesh.hpp"

namespace tetfsi::mesh {

/// Axis-aligned box centred at the origin with the given edge lengths [m] (12 triangles).
/// @throws MeshError if an extent is not > 0
SurfaceMesh make_box(const Eigen::Vector3d& extents);

/// Icosphere of the given radius [m] centred at the origin: the icosahedron, each triangle split
/// into 4 `subdivisions` times, vertices projected to the sphere. 20 * 4^subdivisions triangles,
/// 10 * 4^subdivisions + 2 vertices. Its enclosed volume is below 4/3 pi r^3 (inscribed polyhedron).
/// @throws MeshError if radius <= 0 or subdivisions not in [0, 7]
SurfaceMesh make_sphere(double radius, int subdivisions);

/// Circular cylinder of the given radius and length [m] along z, centred at the origin: a prism over
/// the regular `segments`-gon inscribed in the circle (side quads split in two, caps fanned from their
/// centres). 4 * segments triangles, 2 * segments + 2 vertices.
/// @throws MeshError if radius or length is not > 0 or segments < 3
SurfaceMesh make_cylinder(double radius, double length, int segments);

/// Bowl: a hemispherical shell open toward +y (up in the scenes' convention), of outer radius
/// `radius` and wall `thickness` [m]; the spheres' common centre is the origin and the rim is the
/// annulus radius − thickness <= |x| <= radius in the plane y = 0, so the bowl lies in y <= 0.
/// Latitude rings at polar angles (π/2) k / rings from the bottom pole, `segments` around; the
/// inner and outer surfaces have the same rings. 4 * segments * rings triangles.
/// @throws MeshError if radius or thickness is not > 0, thickness >= radius, segments < 3 or
///         rings < 1
SurfaceMesh make_bowl(double radius, double thickness, int segments, int rings);

/// Sheet: a thin slab centred at the origin, `width` along x, `depth` along y, `thickness` along z
/// [m]. It is a box; the name documents intent (cloth-like solids of the scenes).
/// @throws MeshError if a size is not > 0
SurfaceMesh make_sheet(double width, double depth, double thickness);

}  // namespace tetfsi::mesh
