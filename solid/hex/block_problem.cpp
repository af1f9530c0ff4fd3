#include "solid/hex/block_problem.hpp"

#include <stdexcept>

#include "mesh/io/vtu_reader.hpp"
#include "solid/hex/block_mesh.hpp"

namespace tetfsi::solid::hex {

std::unique_ptr<HexModel> make_model(const BlockProblem& p) {
  mesh::HexMesh mesh = !p.mesh.hexes.empty() ? p.mesh
                       : p.vtu_path.empty()  ? block_mesh(p.lo, p.hi, p.nx, p.ny, p.nz)
                                             : mesh::io::read_hex_mesh_vtu(p.vtu_path);
  return std::make_unique<HexModel>(std::move(mesh), p.material);
}

BoundaryConditions make_conditions(const BlockProblem& p, const mesh::HexMesh& mesh) {
  Eigen::Vector3d lo = mesh.vertices.at(0), hi = lo;
  for (const auto& v : mesh.vertices) { lo = lo.cwiseMin(v); hi = hi.cwiseMax(v); }
  const double tol = 1e-9 * (hi - lo).norm();
  BoundaryConditions bc;
  for (std::size_t i = 0; i < p.conditions.size(); ++i) {
    const auto& c = p.conditions[i];
    const std::string where = "boundary condition " + std::to_string(i);
    const auto nodes = nodes_in_box(mesh, c.lo, c.hi, tol);
    if (nodes.empty()) throw std::invalid_argument(where + ": its box selects no node");
    std::vector<int> comps;
    for (char ch : c.components) {
      if (ch < 'x' || ch > 'z') throw std::invalid_argument(where + ": components must be made of x, y, z");
      comps.push_back(ch - 'x');
    }
    using K = RegionCondition::Kind;
    switch (c.kind) {
      case K::Fixed:
        for (int k : comps) fix_component(bc, nodes, k);
        break;
      case K::Displacement:
        for (int v : nodes) for (int k : comps) bc.prescribed.emplace_back(3 * v + k, c.value(k));
        break;
      case K::NodalForce:
        add_nodal_force(bc, mesh.num_vertices(), nodes, c.value);
        break;
      case K::Traction:
      case K::MomentTraction: {
        const auto faces = boundary_faces_in_box(mesh, c.lo, c.hi, tol);
        if (faces.empty()) throw std::invalid_argument(where + ": its box contains no boundary face");
        if (c.kind == K::Traction) {
          const Eigen::Vector3d t = c.value;
          add_surface_traction(bc, mesh, faces, [t](const Eigen::Vector3d&) { return t; });
        } else {
          add_end_moment_traction(bc, mesh, faces, c.axis, c.moment);
        }
        break;
      }
      case K::MomentRotation: {
        RotatingFace face;
        face.nodes = nodes;
        face.center = c.center;
        face.axis = c.axis;
        face.angle = c.angle;
        bc.rotating_faces.push_back(face);
        break;
      }
    }
  }
  return bc;
}

}  // namespace tetfsi::solid::hex
