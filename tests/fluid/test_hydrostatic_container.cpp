// Hydrostatic pressure in a spherical and in a cylindrical container (issue 16; p = p0 + rho g (z0 - z),
// v = 0): the container surface (mesh::make_sphere, mesh::make_cylinder) meshed by CGAL through
// mesh::build_complex(container, ...), closed (slip walls everywhere), gravity on, fluid at rest.
// A linear pressure with grad p = rho g cancels gravity exactly in the P1 projection on any mesh,
// whatever the container's shape, so one step must give it to solver round-off: relative to
// rho g D (D the container's height), |(p_i - p_ref) - rho g (z_ref - z_i)| <= 1e-9 at every node,
// and |u| <= 1e-9 sqrt(g D).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fluid/fluid_solver.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"

namespace tetfsi::fluid {
namespace {

struct Hydrostatic {
  double pressure_error = 0;  ///< max |(p_i - p_ref) - rho g (z_ref - z_i)| / (rho g D)
  double speed = 0;           ///< max |u| / sqrt(g D)
  int tets = 0;
};

Hydrostatic still_water(const mesh::SurfaceMesh& container, double height, double edge) {
  const double rho = 1000.0, g = 9.81;
  mesh::MeshSizing sizing;
  sizing.edge_length = edge;
  const mesh::TetMesh m = mesh::build_complex(container, {}, sizing, {});
  FluidParams params;
  params.density = rho;
  params.gravity = Eigen::Vector3d(0, 0, -g);
  params.solver.tolerance = 1e-13;
  FluidSolver solver(params);
  solver.initialize(m);
  solver.step(m, {}, 0.01);
  const FluidMesh& fm = solver.mesh();
  Hydrostatic out;
  out.tets = m.num_tets();
  for (int i = 0; i < fm.num_nodes(); ++i) {
    const double expected = rho * g * (fm.nodes[0].z() - fm.nodes[i].z());
    out.pressure_error = std::max(out.pressure_error, std::abs(solver.pressure()[i] - solver.pressure()[0] - expected) /
                                                          (rho * g * height));
  }
  for (const auto& u : solver.fields().velocity) out.speed = std::max(out.speed, u.norm() / std::sqrt(g * height));
  return out;
}

TEST(FluidHydrostatic, SphericalContainer) {
  const double r = 0.3;
  mesh::SurfaceMesh sphere = mesh::make_sphere(r, 2);
  for (auto& v : sphere.vertices) v += Eigen::Vector3d(0.1, -0.2, 0.5);
  const Hydrostatic h = still_water(sphere, 2 * r, 0.1);
  std::printf("sphere r = %.2f m, %d tets: max |p - rho g depth| / (rho g D) = %.3e, max|u| / sqrt(gD) = %.3e\n", r,
              h.tets, h.pressure_error, h.speed);
  EXPECT_GT(h.tets, 100);
  EXPECT_LE(h.pressure_error, 1e-9);
  EXPECT_LE(h.speed, 1e-9);
}

TEST(FluidHydrostatic, CylindricalContainer) {
  const double r = 0.2, length = 0.6;
  const mesh::SurfaceMesh cylinder = mesh::make_cylinder(r, length, 32);  // axis along gravity
  const Hydrostatic h = still_water(cylinder, length, 0.08);
  std::printf("cylinder r = %.2f m, L = %.2f m, %d tets: max |p - rho g depth| / (rho g D) = %.3e, max|u| / sqrt(gD) = "
              "%.3e\n",
              r, length, h.tets, h.pressure_error, h.speed);
  EXPECT_GT(h.tets, 100);
  EXPECT_LE(h.pressure_error, 1e-9);
  EXPECT_LE(h.speed, 1e-9);
}

}  // namespace
}  // namespace tetfsi::fluid
