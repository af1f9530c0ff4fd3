#include "fluid/boundary/boundary_conditions.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "fluid/operators/boundary_flux.hpp"

namespace tetfsi::fluid {
namespace {

/// The patch's velocity at the three vertices of face `bf` [m/s].
std::array<Eigen::Vector3d, 3> inflow_vertex_velocity(const FluidMesh& mesh, const BoundaryPatch& patch,
                                                      const BoundaryFace& bf) {
  std::array<Eigen::Vector3d, 3> v;
  for (int a = 0; a < 3; ++a)
    v[a] = patch.velocity_field ? patch.velocity_field(mesh.nodes[bf.nodes[a]]) : patch.velocity;
  return v;
}

}  // namespace

int outer_face_patch(const FluidMesh& mesh, const BoundaryConditions& bc, const BoundaryFace& face) {
  if (face.other_subdomain >= mesh::solid_subdomain(0)) return -1;
  const Eigen::Vector3d c = (mesh.nodes[face.nodes[0]] + mesh.nodes[face.nodes[1]] + mesh.nodes[face.nodes[2]]) / 3.0;
  for (size_t p = 0; p < bc.patches.size(); ++p)
    if (bc.patches[p].region.contains(c)) return static_cast<int>(p);
  return -1;
}

BoundaryExits boundary_exits(const FluidMesh& mesh, const BoundaryConditions& bc) {
  BoundaryExits e;
  e.rule.assign(mesh.boundary_faces.size(), ExitRule::kClamp);
  e.inflow_velocity.resize(mesh.boundary_faces.size());
  for (size_t f = 0; f < mesh.boundary_faces.size(); ++f) {
    const int p = outer_face_patch(mesh, bc, mesh.boundary_faces[f]);
    if (p < 0) continue;
    if (bc.patches[p].kind == FaceKind::kOpen) e.rule[f] = ExitRule::kOpen;
    if (bc.patches[p].kind == FaceKind::kInflow && bc.patches[p].velocity_field) {
      e.rule[f] = ExitRule::kInflow;
      e.inflow_velocity[f] = inflow_vertex_velocity(mesh, bc.patches[p], mesh.boundary_faces[f]);
    }
  }
  return e;
}

ClassifiedBoundary classify_boundary(const FluidMesh& mesh, const BoundaryConditions& bc) {
  ClassifiedBoundary cb;
  const size_t nb = mesh.boundary_faces.size();
  cb.face_kind.assign(nb, FaceKind::kWall);
  cb.face_patch.assign(nb, -1);
  cb.node_kind.assign(mesh.num_nodes(), NodeKind::kInterior);
  if (!bc.solid_vertex_velocity.empty()) {
    int max_vertex = -1;
    for (int v : mesh.node_to_mesh_vertex) max_vertex = std::max(max_vertex, v);
    if (static_cast<int>(bc.solid_vertex_velocity.size()) <= max_vertex)
      throw std::invalid_argument("classify_boundary: solid_vertex_velocity has " +
                                  std::to_string(bc.solid_vertex_velocity.size()) +
                                  " entries but the mesh has vertex " + std::to_string(max_vertex));
  }
  auto raise = [&](int node, NodeKind k) {
    if (static_cast<int>(k) > static_cast<int>(cb.node_kind[node])) cb.node_kind[node] = k;
  };
  for (size_t f = 0; f < nb; ++f) {
    const BoundaryFace& bf = mesh.boundary_faces[f];
    NodeKind nk = NodeKind::kWall;
    if (bf.other_subdomain >= mesh::solid_subdomain(0)) {
      cb.face_kind[f] = FaceKind::kInterface;
      nk = NodeKind::kInterface;
      if (!bc.solid_vertex_velocity.empty()) {
        std::array<Eigen::Vector3d, 3> v;
        for (int a = 0; a < 3; ++a) v[a] = bc.solid_vertex_velocity[mesh.node_to_mesh_vertex[bf.nodes[a]]];
        cb.flux_faces.push_back(static_cast<int>(f));
        cb.flux_velocity.push_back(v);
      }
    } else {
      cb.face_patch[f] = outer_face_patch(mesh, bc, bf);
      if (cb.face_patch[f] >= 0) cb.face_kind[f] = bc.patches[cb.face_patch[f]].kind;
      if (cb.face_kind[f] == FaceKind::kInflow) {
        nk = NodeKind::kInflow;
        cb.flux_faces.push_back(static_cast<int>(f));
        cb.flux_velocity.push_back(inflow_vertex_velocity(mesh, bc.patches[cb.face_patch[f]], bf));
      } else if (cb.face_kind[f] == FaceKind::kOpen) {
        nk = NodeKind::kOpen;
        cb.closed = false;
      }
    }
    for (int a = 0; a < 3; ++a) raise(bf.nodes[a], nk);
  }
  cb.flux = boundary_flux(mesh, cb.flux_faces, cb.flux_velocity);
  if (bc.balance_inflow && cb.closed) {
    std::vector<int> inflow_faces;
    std::vector<std::array<Eigen::Vector3d, 3>> inflow_velocity;
    for (size_t k = 0; k < cb.flux_faces.size(); ++k)
      if (cb.face_kind[cb.flux_faces[k]] == FaceKind::kInflow) {
        inflow_faces.push_back(cb.flux_faces[k]);
        inflow_velocity.push_back(cb.flux_velocity[k]);
      }
    const Eigen::VectorXd w = boundary_flux(mesh, inflow_faces, inflow_velocity).cwiseAbs();
    const double net = cb.flux.sum(), wsum = w.sum();
    if (wsum > 0.0) {
      cb.flux -= (net / wsum) * w;
      cb.flux_imbalance = net / cb.flux.cwiseAbs().sum();
    }
  }
  return cb;
}

}  // namespace tetfsi::fluid
