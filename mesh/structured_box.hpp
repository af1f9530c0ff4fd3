#pragma once
/// @file structured_box.hpp
/// Structured tetrahedral meshes of an axis-aligned box, without CGAL: each of the
/// nx * ny * nz cells is split into 6 tets around its main diagonal (Kuhn / Freudenthal
/// subdivision), so neighbouring cells match face to face. Used by tests and benchmarks
/// that need exact, reproducible meshes (beams, Taylor-Green boxes).
#include <Eigen/Core>

#include "mesh/tet_mesh.hpp"

namespace tetfsi::mesh {

/// Tet mesh of the box [lo, hi] with nx x ny x nz cells (6 tets per cell).
/// @param lo, hi      opposite corners [m], hi > lo componentwise
/// @param nx, ny, nz  cells per axis, >= 1
/// @param subdomain   label given to every tet
/// @return mesh with (nx+1)(ny+1)(nz+1) vertices, vertex (i,j,k) at index i + (nx+1)(j + (ny+1)k),
///         and 6 nx ny nz positively oriented tets
/// @throws std::invalid_argument on a non-positive size or count
TetMesh structured_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz,
                       int subdomain = kFluidSubdomain);

}  // namespace tetfsi::mesh
