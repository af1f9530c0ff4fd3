#include "solid/loads/region_conditions.hpp"

#include <algorithm>
#include <stdexcept>

namespace tetfsi::solid {

BoundaryConditions make_conditions(const std::vector<RegionCondition>& conditions, const LoadedMesh& mesh) {
  if (mesh.vertices.empty()) throw std::invalid_argument("make_conditions: the mesh has no vertices");
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const auto& v : mesh.vertices) { lo = lo.cwiseMin(v); hi = hi.cwiseMax(v); }
  const double tol = 1e-9 * (hi - lo).norm();
  const int n = static_cast<int>(mesh.vertices.size());
  BoundaryConditions bc;
  for (std::size_t i = 0; i < conditions.size(); ++i) {
    const auto& c = conditions[i];
    const std::string where = "boundary condition " + std::to_string(i);
    const auto nodes = vertices_in_box(mesh.vertices, c.lo, c.hi, tol);
    if (nodes.empty()) throw std::invalid_argument(where + ": its box selects no node");
    std::vector<int> comps;
    for (char ch : c.components) {
      if (ch < 'x' || ch > 'z') throw std::invalid_argument(where + ": components must be made of x, y, z");
      comps.push_back(ch - 'x');
    }
    using K = RegionCondition::Kind;
    const bool surface = c.kind == K::Traction || c.kind == K::MomentTraction || c.kind == K::Pressure;
    std::vector<SurfaceFace> faces;
    if (surface) {
      faces = faces_in_box(mesh.boundary, mesh.vertices, c.lo, c.hi, tol);
      if (faces.empty()) throw std::invalid_argument(where + ": its box contains no boundary face");
    }
    switch (c.kind) {
      case K::Fixed:
        for (int k : comps) fix_component(bc, nodes, k);
        break;
      case K::Displacement:
        for (int v : nodes) for (int k : comps) bc.prescribed.emplace_back(3 * v + k, c.value(k));
        break;
      case K::NodalForce:
        add_nodal_force(bc, n, nodes, c.value);
        break;
      case K::Traction: {
        const Eigen::Vector3d t = c.value;
        add_surface_traction(bc, mesh.vertices, faces, [t](const Eigen::Vector3d&) { return t; });
        break;
      }
      case K::MomentTraction:
        add_end_moment_traction(bc, mesh.vertices, faces, c.axis, c.moment);
        break;
      case K::BodyForce:
        add_body_force(bc, mesh.masses, mesh.density, nodes, c.value);
        break;
      case K::Pressure:
        bc.pressures.push_back({faces, c.pressure});
        break;
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
  // Overlapping `fixed` regions fix an edge node's dof twice: no contradiction in a scene (the
  // solver refuses a dof constrained twice, so it gets each once).
  auto& fixed = bc.fixed_dofs;
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  return bc;
}

}  // namespace tetfsi::solid
