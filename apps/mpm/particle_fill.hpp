#pragma once
/// @file particle_fill.hpp
/// Particle lattices of the body shapes of the `mpm` block: box, sphere, cylinder and closed
/// surface files (assimp import, mesh/surface_import.hpp).
#include <functional>

#include "mesh/surface_mesh.hpp"
#include "fluid/mpm/grid.hpp"

namespace tetfsi::mpm_setup {

/// A shape to fill: the lattice box [lo, hi] (particle centres lo + (i + 1/2) dx, see
/// mpm::sample_lattice) and the inside test (none: the whole box).
struct FillRegion {
  mpm::Vec3 lo, hi;
  std::function<bool(const mpm::Vec3&)> inside;
};

/// Inside test of a closed triangle surface by the parity of the crossings of a ray along +z (the
/// ray's x, y moved by 1e-9 of the bounding box, so that it does not run through edges of meshes
/// built on the same lattice). Crossings are found per (x, y) column and cached, so a lattice of
/// n^3 points costs n^2 ray casts.
std::function<bool(const mpm::Vec3&)> inside_surface(const mesh::SurfaceMesh& s);

}  // namespace tetfsi::mpm_setup
