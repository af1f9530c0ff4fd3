#pragma once
/// @file block_problem.hpp
/// Plain description of a hex problem as a scene gives it (block or VTU mesh, material, boundary
/// conditions by region, load steps), turned into a HexModel + BoundaryConditions. The scene
/// parser (apps/) fills these structs from JSON; nothing here reads files except the VTU mesh.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "solid/analysis/static_solver.hpp"
#include "solid/hex/hex_model.hpp"
#include "solid/loads/region_conditions.hpp"

namespace tetfsi::solid::hex {

/// Conditions by region (shared with tet solids: solid/loads/region_conditions.hpp).
using RegionCondition = solid::RegionCondition;
using solid::BoundaryConditions;

struct BlockProblem {
  // Mesh: `mesh` if it has hexes (placed and checked by the caller, e.g. the scene's hex_mesh_of),
  // else a VTU file (vtu_path non-empty), else the block [lo, hi] with nx x ny x nz hexes.
  mesh::HexMesh mesh;
  std::string vtu_path;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Ones();
  int nx = 1, ny = 1, nz = 1;
  Material material;
  Hex8Formulation formulation = Hex8Formulation::Enhanced;
  std::vector<RegionCondition> conditions;
  solid::StaticOptions options;
};

/// Builds the mesh and the model. @throws std::invalid_argument / std::runtime_error naming the cause
std::unique_ptr<HexModel> make_model(const BlockProblem& problem);
/// Builds the boundary conditions on the model's mesh (solid::make_conditions on its boundary quads).
/// @throws std::invalid_argument if a region selects no node (naming the condition's index)
BoundaryConditions make_conditions(const BlockProblem& problem, const HexModel& model);

}  // namespace tetfsi::solid::hex
