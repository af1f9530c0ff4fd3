#pragma once
/// @file fluid_output.hpp
/// VTU grid of the fluid state for ParaView: point data pressure [Pa], velocity [m/s] (node-averaged,
/// the reconstruction the advection uses), smoke, temperature; cell data velocity (the projected,
/// per-tet unknowns), smoke, temperature.
#include "fluid/advection/semi_lagrangian.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "mesh/io/vtu_writer.hpp"

namespace tetfsi::fluid {

mesh::io::UnstructuredGrid make_fluid_grid(const FluidMesh& mesh, const FluidFields& fields,
                                           const Eigen::VectorXd& pressure);

/// Adds a free-surface liquid's fields to `grid` (made by make_fluid_grid): point data
/// "level_set" [m] (negative in the liquid; its zero contour is the surface) and cell data
/// "liquid_fraction" |Omega_t| / V_t.
void add_liquid_fields(mesh::io::UnstructuredGrid& grid, const FluidMesh& mesh, const Eigen::VectorXd& level_set,
                       const std::vector<double>& liquid_volume);

}  // namespace tetfsi::fluid
