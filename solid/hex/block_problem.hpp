#pragma once
/// @file block_problem.hpp
/// Plain description of a hex problem as a scene gives it (block or VTU mesh, material, boundary
/// conditions by region, load steps), turned into a HexModel + BoundaryConditions. The scene
/// parser (apps/) fills these structs from JSON; nothing here reads files except the VTU mesh.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "solid/hex/boundary_conditions.hpp"
#include "solid/hex/hex_model.hpp"
#include "solid/hex/static_solver.hpp"

namespace tetfsi::solid::hex {

/// One boundary condition on the nodes (or boundary faces) inside the box [lo, hi] (+-1e-9 L).
struct RegionCondition {
  enum class Kind {
    Fixed,            ///< all components held at 0; `components` restricts to some ("xyz", "z", ...)
    Displacement,     ///< `value` [m] prescribed at lambda = 1 on `components`
    NodalForce,       ///< `value` [N] on every node of the region
    Traction,         ///< `value` [Pa], dead, on the boundary faces in the region
    MomentRotation,   ///< rigid end rotation by `angle` [rad] about `axis` through `center`, free
                      ///< translation (pure follower couple; RotatingFace)
    MomentTraction,   ///< dead linear traction with couple `moment` [N m] about `axis`
  } kind = Kind::Fixed;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  std::string components = "xyz";
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< MomentRotation: a point on the axis
  double angle = 0.0;
  double moment = 0.0;
};

struct BlockProblem {
  // Mesh: `mesh` if it has hexes (placed and checked by the caller, e.g. the scene's hex_mesh_of),
  // else a VTU file (vtu_path non-empty), else the block [lo, hi] with nx x ny x nz hexes.
  mesh::HexMesh mesh;
  std::string vtu_path;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Ones();
  int nx = 1, ny = 1, nz = 1;
  Material material;
  std::vector<RegionCondition> conditions;
  StaticOptions options;
};

/// Builds the mesh and the model. @throws std::invalid_argument / std::runtime_error naming the cause
std::unique_ptr<HexModel> make_model(const BlockProblem& problem);
/// Builds the boundary conditions on the model's mesh.
/// @throws std::invalid_argument if a region selects no node (naming the condition's index)
BoundaryConditions make_conditions(const BlockProblem& problem, const mesh::HexMesh& mesh);

}  // namespace tetfsi::solid::hex
