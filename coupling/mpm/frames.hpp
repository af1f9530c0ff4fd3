#pragma once
/// @file frames.hpp
/// VTU frames of an MPM-membrane model with the shared writer (mesh/io/vtu_writer.hpp):
/// particles as a point cloud (VTK_VERTEX) with pressure, density, velocity; membranes as
/// VtkCell::Quad cells with the membrane stress (global tensor, 9 components) per cell.
#include "fluid/mpm/mpm_solver.hpp"
#include "mesh/io/vtu_writer.hpp"
#include "solid/membrane/membrane.hpp"

namespace tetfsi::mpm_contact {

/// Point fields: "velocity" (3), "pressure" (-tr sigma / 3), "density", "internal_energy" (E per
/// reference volume for fluids).
mesh::io::UnstructuredGrid particle_frame(const mpm::MpmSolver& mpm);
/// Point field "velocity" (3); cell field "stress" (9, global Cauchy stress in the membrane).
mesh::io::UnstructuredGrid membrane_frame(const membrane::Membrane& membrane);

}  // namespace tetfsi::mpm_contact
