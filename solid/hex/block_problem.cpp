#include "solid/hex/block_problem.hpp"

#include <stdexcept>

#include "mesh/io/vtu_reader.hpp"
#include "solid/hex/block_mesh.hpp"

namespace tetfsi::solid::hex {

std::unique_ptr<HexModel> make_model(const BlockProblem& p) {
  mesh::HexMesh mesh = !p.mesh.hexes.empty() ? p.mesh
                       : p.vtu_path.empty()  ? block_mesh(p.lo, p.hi, p.nx, p.ny, p.nz)
                                             : mesh::io::read_hex_mesh_vtu(p.vtu_path);
  return std::make_unique<HexModel>(std::move(mesh), p.material, p.formulation);
}

BoundaryConditions make_conditions(const BlockProblem& p, const HexModel& model) {
  const mesh::HexMesh& mesh = model.mesh();
  solid::LoadedMesh loaded;
  loaded.vertices = mesh.vertices;
  Eigen::Vector3d lo = mesh.vertices.at(0), hi = lo;
  for (const auto& v : mesh.vertices) { lo = lo.cwiseMin(v); hi = hi.cwiseMax(v); }
  for (const auto& q : boundary_faces_in_box(mesh, lo, hi, 1e-9 * (hi - lo).norm()))
    loaded.boundary.push_back({q[0], q[1], q[2], q[3]});
  loaded.masses = model.lumped_masses();
  loaded.density = model.material().density;
  return solid::make_conditions(p.conditions, loaded);
}

}  // namespace tetfsi::solid::hex
