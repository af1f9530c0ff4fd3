// Nested surfaces in the Mesh_3 complex: a spherical shell (outer radius R, cavity radius r) whose
// cavity is fluid, alone (mesh_filled_shell, the filled toy) and inside a fluid box
// (build_complex with cavities). Checked: labels, shell and cavity volumes against 4/3 pi (R^3 -
// r^3) and 4/3 pi r^3 within the facet distance, and a conforming cavity interface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/primitives.hpp"
#include "mesh/quality.hpp"
#include "mesh/surface_checks.hpp"

using namespace tetfsi::mesh;

namespace {

constexpr double kR = 0.3, kr = 0.22;  // outer and cavity radius [m]

double subdomain_volume(const TetMesh& m, int label) {
  double v = 0.0;
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.subdomain[t] == label) v += signed_volume(m, t);
  return v;
}

double ball(double r) { return 4.0 / 3.0 * M_PI * r * r * r; }

/// Faces of fluid tets that are not shared with another fluid tet: for each, the labels of the
/// tets on its other side (empty: a mesh boundary face).
struct FluidBoundary {
  int faces = 0, to_solid = 0, to_nothing = 0, to_several = 0;
  double max_radius = 0.0, min_radius = 1e300;  // distance of the face vertices from the origin
};
FluidBoundary fluid_boundary(const TetMesh& m) {
  std::map<std::array<int, 3>, std::vector<int>> tets_of_face;
  for (int t = 0; t < m.num_tets(); ++t)
    for (const auto& f : kTetFaceVertices) {
      std::array<int, 3> key{m.tets[t][f[0]], m.tets[t][f[1]], m.tets[t][f[2]]};
      std::sort(key.begin(), key.end());
      tets_of_face[key].push_back(t);
    }
  FluidBoundary out;
  for (const auto& [key, tets] : tets_of_face) {
    const int fluid = static_cast<int>(std::count_if(tets.begin(), tets.end(), [&](int t) {
      return m.subdomain[t] == kFluidSubdomain;
    }));
    if (fluid != 1) continue;  // interior fluid face (2) or not a fluid face (0)
    ++out.faces;
    if (tets.size() == 1) ++out.to_nothing;
    else if (tets.size() > 2) ++out.to_several;
    else ++out.to_solid;  // the other tet is not fluid
    for (int v : key) {
      out.max_radius = std::max(out.max_radius, m.vertices[v].norm());
      out.min_radius = std::min(out.min_radius, m.vertices[v].norm());
    }
  }
  return out;
}

MeshSizing shell_sizing() {
  MeshSizing sizing;
  sizing.edge_length = 0.05;
  sizing.facet_distance = 0.002;
  return sizing;
}

/// |V_meshed - V_exact| for a sphere of radius rho meshed from an icosphere: the meshed facets lie
/// within the facet distance of the icosphere (error <= distance x area), which lies within its own
/// volume deficit of the exact sphere.
double sphere_volume_tolerance(double rho, const SurfaceMesh& icosphere, double facet_distance) {
  return facet_distance * 4.0 * M_PI * rho * rho + (ball(rho) - enclosed_volume(icosphere));
}

}  // namespace

TEST(ShellMesher, FilledShellHasExactVolumesAndAConformingCavity) {
  const SurfaceMesh outer = make_sphere(kR, 4), cavity = make_sphere(kr, 4);
  const MeshSizing sizing = shell_sizing();
  const TetMesh m = mesh_filled_shell(outer, cavity, sizing);
  const QualityReport q = quality_report(m);
  std::printf("filled shell: %s\n", q.summary().c_str());
  ASSERT_EQ(q.tets_per_subdomain.size(), 2u);  // labels: fluid 1 and solid 2 only
  EXPECT_GT(q.tets_per_subdomain.at(kFluidSubdomain), 100);
  EXPECT_GT(q.tets_per_subdomain.at(solid_subdomain(0)), 100);
  EXPECT_EQ(q.inverted + q.degenerate, 0);

  const double v_shell = subdomain_volume(m, solid_subdomain(0)), v_cavity = subdomain_volume(m, kFluidSubdomain);
  const double tol_outer = sphere_volume_tolerance(kR, outer, sizing.facet_distance);
  const double tol_cavity = sphere_volume_tolerance(kr, cavity, sizing.facet_distance);
  std::printf("shell volume %.6g (exact %.6g, rel. %.2e), cavity %.6g (exact %.6g, rel. %.2e)\n", v_shell,
              ball(kR) - ball(kr), v_shell / (ball(kR) - ball(kr)) - 1, v_cavity, ball(kr), v_cavity / ball(kr) - 1);
  EXPECT_NEAR(v_cavity, ball(kr), tol_cavity);
  EXPECT_NEAR(v_shell, ball(kR) - ball(kr), tol_outer + tol_cavity);

  // The fluid's whole boundary is the cavity interface: every boundary face of the fluid is shared
  // with exactly one solid tet, and lies on the cavity sphere (within the facet distance).
  const FluidBoundary fb = fluid_boundary(m);
  EXPECT_GT(fb.faces, 200);
  EXPECT_EQ(fb.to_solid, fb.faces);
  EXPECT_EQ(fb.to_nothing + fb.to_several, 0);
  EXPECT_LT(fb.max_radius, kr + 1e-9);
  EXPECT_GT(fb.min_radius, kr - 2.0 * sizing.facet_distance);
  // check_interface: the only defect is the shell's outer surface, which faces nothing.
  const InterfaceCheck ic = check_interface(m);
  EXPECT_EQ(ic.interface_faces, fb.faces);
  EXPECT_EQ(ic.overshared_faces + ic.solid_solid_faces + ic.misoriented_faces, 0) << ic.first_defect;
  EXPECT_GT(ic.exposed_solid_faces, fb.faces);  // the outer sphere is larger than the cavity
}

TEST(ShellMesher, ShellWithCavityInAFluidBox) {
  const SurfaceMesh outer = make_sphere(kR, 4), cavity = make_sphere(kr, 4);
  MeshSizing sizing = shell_sizing();
  sizing.edge_length = 0.12;
  sizing.edge_length_near_solids = 0.05;
  sizing.grading_distance = 0.2;
  const Eigen::Vector3d lo(-0.6, -0.6, -0.6), hi(0.6, 0.6, 0.6);
  const TetMesh m = build_complex(lo, hi, {outer}, sizing, {cavity});
  const InterfaceCheck ic = check_interface(m);
  EXPECT_TRUE(ic.conforming()) << ic.first_defect;
  // Fluid inside the cavity and outside the shell, none in the wall.
  double v_inner_fluid = 0.0, v_outer_fluid = 0.0;
  for (int t = 0; t < m.num_tets(); ++t) {
    if (m.subdomain[t] != kFluidSubdomain) continue;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : m.tets[t]) c += 0.25 * m.vertices[v];
    EXPECT_TRUE(c.norm() < kr || c.norm() > kR) << "fluid tet " << t << " in the wall at radius " << c.norm();
    (c.norm() < kr ? v_inner_fluid : v_outer_fluid) += signed_volume(m, t);
  }
  const double tol_outer = sphere_volume_tolerance(kR, outer, sizing.facet_distance);
  const double tol_cavity = sphere_volume_tolerance(kr, cavity, sizing.facet_distance);
  EXPECT_NEAR(v_inner_fluid, ball(kr), tol_cavity);
  EXPECT_NEAR(v_outer_fluid, (hi - lo).prod() - ball(kR), tol_outer);
  EXPECT_NEAR(subdomain_volume(m, solid_subdomain(0)), ball(kR) - ball(kr), tol_outer + tol_cavity);
  // Interface = both spheres' triangles: more than the filled shell's cavity alone.
  EXPECT_GT(ic.interface_faces, fluid_boundary(mesh_filled_shell(outer, cavity, shell_sizing())).faces);
}

TEST(ShellMesher, BadCavitiesAreNamed) {
  const SurfaceMesh outer = make_sphere(kR, 2);
  const auto expect_error = [](auto&& make, const std::string& needle) {
    try {
      make();
      ADD_FAILURE() << "expected MeshError containing '" << needle << "'";
    } catch (const MeshError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  // A cavity larger than the shell, and one that pokes out of it.
  expect_error([&] { mesh_filled_shell(outer, make_sphere(1.5 * kR, 2), shell_sizing()); }, "not strictly inside");
  SurfaceMesh shifted = make_sphere(kr, 2);
  for (auto& v : shifted.vertices) v.x() += 0.15;
  expect_error([&] { mesh_filled_shell(outer, shifted, shell_sizing()); }, "shell cavity");
  expect_error([&] { build_complex({-1, -1, -1}, {1, 1, 1}, {outer}, shell_sizing(), {shifted}); },
               "solid 0 cavity");
  expect_error([&] { build_complex({-1, -1, -1}, {1, 1, 1}, {outer, outer}, shell_sizing(), {shifted}); },
               "cavity surfaces for 2 solids");
}
