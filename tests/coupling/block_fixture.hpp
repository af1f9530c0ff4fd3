#pragma once
/// @file block_fixture.hpp
/// A soft solid block in a box of water, on a structured tet mesh: the fluid fills [0,1]³ with an
/// open top (p = 0 at z = 1), the solid is the cells of its middle third (whole cells, rounded to
/// the grid: where 1/3 cut through cells, tets hanging on by an edge made the StVK tangent, and so
/// A, indefinite after one step at 32³). Light rubber (ρ_s = 500 kg/m³, E = 1e5 Pa) under gravity
/// in water, h = 1/60 s. Used by the solver tests and by bench_coupling (per-step solver cost).
#include <cmath>
#include <memory>
#include <vector>

#include "coupling/coupled_stepper.hpp"
#include "mesh/structured_box.hpp"

namespace tetfsi::test {

inline mesh::TetMesh block_in_box(int cells) {
  mesh::TetMesh m = mesh::structured_box({0, 0, 0}, {1, 1, 1}, cells, cells, cells);
  const double lo = std::round(cells / 3.0) / cells, hi = std::round(2 * cells / 3.0) / cells;
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : m.tets[t]) c += m.vertices[v] / 4;
    const bool inside = (c.array() > lo).all() && (c.array() < hi).all();
    m.subdomain[t] = inside ? mesh::solid_subdomain(0) : mesh::kFluidSubdomain;
  }
  return m;
}

/// Water (ρ = 1000 kg/m³), BoomerAMG-PCG pressure solve to `tolerance`: the fluid of the block
/// scene and of the fluid-only step it is compared with.
inline fluid::FluidParams block_fluid(double tolerance) {
  fluid::FluidParams fp;
  fp.density = 1000;
  fp.solver.tolerance = tolerance;
  return fp;
}

/// The open top face z = 1.
inline fluid::BoundaryPatch block_open_top() {
  fluid::BoundaryPatch open;
  open.kind = fluid::FaceKind::kOpen;
  open.region.lo = {-1, -1, 1 - 1e-9};
  open.region.hi = {2, 2, 1 + 1e-9};
  return open;
}

inline std::unique_ptr<coupling::CoupledStepper> make_block_scene(const mesh::TetMesh& m, coupling::CoupledSolverKind kind,
                                                                  coupling::CoupledSolverOptions options) {
  solid::TetMaterial mat;
  mat.density = 500;
  mat.youngs_modulus = 1e5;
  mat.poisson_ratio = 0.3;
  coupling::CoupledSettings cs;
  cs.time_step = 1.0 / 60;
  cs.solver = kind;
  cs.solver_options = std::move(options);
  cs.solid_gravity = {0, 0, -9.81};
  auto s = std::make_unique<coupling::CoupledStepper>(m, block_fluid(cs.solver_options.tolerance),
                                                      std::vector<solid::TetMaterial>{mat}, cs);
  s->fluid_boundary().patches.push_back(block_open_top());
  return s;
}

}  // namespace tetfsi::test
