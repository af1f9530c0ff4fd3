// H and J = Hᵀ over shared interface triangles reproduce exact integral identities:
// Archimedes' buoyancy for a hydrostatic pressure, and the divergence theorem for the flux.
#include <gtest/gtest.h>

#include <map>

#include "coupling/interface_maps.hpp"
#include "mesh/structured_box.hpp"

using namespace tetfsi;

namespace {

// A solid box [lo, hi] meshed with structured tets; its boundary triangles are the interface,
// with normals pointing into the solid (out of the surrounding fluid). Every vertex of the box is
// a solid node (index = mesh vertex), every surface vertex has a pressure unknown.
struct BoxInterface {
  mesh::TetMesh mesh;
  std::vector<coupling::InterfaceTriangle> triangles;
  coupling::InterfaceDofs dofs;
  int num_pressures = 0;
  double volume = 0;
};

BoxInterface make_box_interface(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int n) {
  BoxInterface b;
  b.mesh = mesh::structured_box(lo, hi, n, n + 1, n + 2, mesh::solid_subdomain(0));
  b.volume = (hi - lo).prod();
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> faces;  // sorted -> (count, oriented)
  for (const auto& t : b.mesh.tets) {
    // Faces opposite each vertex, oriented with outward normals of the tet.
    const std::array<std::array<int, 3>, 4> local = {{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
    for (const auto& f : local) {
      std::array<int, 3> oriented{t[f[0]], t[f[1]], t[f[2]]};
      std::array<int, 3> key = oriented;
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      ++e.first;
      e.second = oriented;
    }
  }
  b.dofs.solid_node.resize(b.mesh.num_vertices());
  b.dofs.pressure_index.assign(b.mesh.num_vertices(), -1);
  for (int v = 0; v < b.mesh.num_vertices(); ++v) b.dofs.solid_node[v] = v;
  for (const auto& [key, entry] : faces) {
    if (entry.first != 1) continue;
    const auto& f = entry.second;
    const auto& x = b.mesh.vertices;
    const Eigen::Vector3d outward = 0.5 * (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
    b.triangles.push_back({f, -outward});  // out of the fluid = into the solid
    for (int v : f)
      if (b.dofs.pressure_index[v] < 0) b.dofs.pressure_index[v] = b.num_pressures++;
  }
  return b;
}

}  // namespace

TEST(InterfaceMaps, HydrostaticPressureGivesArchimedesBuoyancy) {
  const BoxInterface b = make_box_interface({-0.2, -0.1, -0.3}, {0.3, 0.2, 0.1}, 3);
  const auto H = coupling::interface_flux_map(b.triangles, b.dofs, b.num_pressures, b.mesh.num_vertices());
  const double rho = 1000, g = 9.81, z0 = 0.5;
  Eigen::VectorXd p(b.num_pressures);
  for (int v = 0; v < b.mesh.num_vertices(); ++v)
    if (b.dofs.pressure_index[v] >= 0) p[b.dofs.pressure_index[v]] = rho * g * (z0 - b.mesh.vertices[v].z());
  const Eigen::VectorXd f = H.transpose() * p;  // J p: nodal forces
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int a = 0; a < b.mesh.num_vertices(); ++a) total += f.segment<3>(3 * a);
  const double buoyancy = rho * g * b.volume;
  EXPECT_NEAR(total.z(), buoyancy, 1e-12 * buoyancy);
  EXPECT_NEAR(total.x(), 0.0, 1e-12 * buoyancy);
  EXPECT_NEAR(total.y(), 0.0, 1e-12 * buoyancy);
}

TEST(InterfaceMaps, UniformExpansionFluxIsThreeTimesVolumeRate) {
  const BoxInterface b = make_box_interface({0.1, 0.2, 0.3}, {0.6, 0.4, 0.9}, 2);
  const auto H = coupling::interface_flux_map(b.triangles, b.dofs, b.num_pressures, b.mesh.num_vertices());
  const double eps = 0.7;  // u(x) = ε x, so ∮ u·n dA = 3 ε V over the outward normal
  Eigen::VectorXd u(3 * b.mesh.num_vertices());
  for (int a = 0; a < b.mesh.num_vertices(); ++a) u.segment<3>(3 * a) = eps * b.mesh.vertices[a];
  // Σ_i (H u)_i = ∮ (Σ_i φ_i) u·n_T dA with n_T into the solid: −3εV.
  EXPECT_NEAR((H * u).sum(), -3 * eps * b.volume, 1e-12);
  // A rigid translation moves no volume.
  for (int a = 0; a < b.mesh.num_vertices(); ++a) u.segment<3>(3 * a) = Eigen::Vector3d(1.0, -2.0, 0.5);
  EXPECT_NEAR((H * u).sum(), 0.0, 1e-12);
}

TEST(InterfaceMaps, PressureWorkEqualsFluxWork) {
  // pᵀ(H u) == (J p)ᵀ u with J = Hᵀ: the same number computed both ways.
  const BoxInterface b = make_box_interface({0, 0, 0}, {1, 1, 1}, 2);
  const auto H = coupling::interface_flux_map(b.triangles, b.dofs, b.num_pressures, b.mesh.num_vertices());
  const Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(b.num_pressures, -3.0, 5.0);
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(3 * b.mesh.num_vertices(), 2.0, -1.0);
  const Eigen::SparseMatrix<double> J = H.transpose();
  EXPECT_NEAR(p.dot(H * u), (J * p).dot(u), 1e-12 * std::abs(p.dot(H * u)));
}

TEST(InterfaceMaps, RejectsTriangleOffTheSolid) {
  BoxInterface b = make_box_interface({0, 0, 0}, {1, 1, 1}, 1);
  b.dofs.solid_node[b.triangles[0].vertices[1]] = -1;
  EXPECT_THROW(coupling::interface_flux_map(b.triangles, b.dofs, b.num_pressures, b.mesh.num_vertices()),
               std::invalid_argument);
}
