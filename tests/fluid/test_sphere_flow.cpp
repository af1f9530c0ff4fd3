// Sphere cases on CGAL complex meshes (mesh::build_complex):
//  - potential flow past a fixed sphere (Lamb 1932, §92): one projection of a uniform flow;
//    surface C_p against 1 - (9/4) sin^2(theta).
//  - added mass of an oscillating sphere: prescribed x(t) = A sin(w t); pressure force = -1/2 rho V x''
//    (Lamb 1932, §92).
// Both impose the exact unbounded far field on the box faces (apps/bench/fluid/sphere_cases.hpp), so
// the small box (L = 2a; the CGAL mesher loses the sphere for L >= 3a at the time of writing) needs no
// blockage correction.
#include <gtest/gtest.h>

#include <cmath>

#include "fluid/fluid_solver.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"
#include "apps/bench/fluid/sphere_cases.hpp"

namespace tetfsi::fluid {
namespace {

constexpr double kA = 0.5, kL = 1.0;

/// The two CI meshes (h_near/a = 0.24 and 0.16), each built at most once per process: CGAL meshing
/// dominates the test time.
const mesh::TetMesh& sphere_mesh(int level) {
  if (level == 0) {
    static const mesh::TetMesh coarse = validation::sphere_in_box(kA, kL, 0.12, 0.24);
    return coarse;
  }
  static const mesh::TetMesh fine = validation::sphere_in_box(kA, kL, 0.08, 0.16);
  return fine;
}

TEST(FluidSphere, PotentialFlowSurfacePressureCoefficient) {
  const validation::PotentialFlowResult coarse = validation::potential_flow(sphere_mesh(0), kA, kL);
  const validation::PotentialFlowResult fine = validation::potential_flow(sphere_mesh(1), kA, kL);
  for (const auto* r : {&coarse, &fine})
    std::printf("potential flow: %d tets, h_surface %.3f: surface Cp rms error %.4f (max %.4f); Cp at tet centroids "
                "rms error %.4f; stagnation Cp %.3f (exact 1), equator Cp %.3f (exact -1.25); max|div| h/U %.1e\n",
                r->tets, r->h_surface, r->surface_rms, r->surface_max, r->centroid_rms, r->cp_stagnation, r->cp_equator,
                r->max_div_scaled);
  EXPECT_LT(fine.surface_rms, coarse.surface_rms);
  EXPECT_LT(fine.centroid_rms, coarse.centroid_rms);
  // Stated bound: the tet next to the surface samples the flow about h/4 off the wall, where the
  // potential-flow speed is lower by about (h/4)/a relative, i.e. a C_p offset of about
  // 2 * (9/4) (h/4) / a = 0.22 at h/a = 0.2 at the equator; rms over the sphere about half of that.
  EXPECT_LT(fine.surface_rms, 0.15);
  EXPECT_LE(fine.max_div_scaled, 1e-8);
}

TEST(FluidSphere, AddedMassOfAnOscillatingSphere) {
  const validation::AddedMassResult fine = validation::added_mass(sphere_mesh(1), kA, kL, 20);
  for (const auto* r : {&fine})
    std::printf("added mass: %d tets: oscillating %.2f kg, impulsive start %.2f kg, 1/2 rho V = %.2f kg: rel. error "
                "%+.4f (impulsive %+.4f); max|div| h/U %.1e\n",
                r->tets, r->measured, r->impulsive, r->ideal, r->measured / r->ideal - 1.0,
                r->impulsive / r->ideal - 1.0, r->max_div_scaled);
  // The discrete added mass converges at about O(h^2) (bench_fluid: -10.7%, -4.8%, -2.4% at
  // h_near/a = 0.24, 0.16, 0.11); the benchmark checks 5% at 0.11. CI band at h_near/a = 0.16: 8%.
  EXPECT_NEAR(fine.measured / fine.ideal, 1.0, 0.08);
  // Time stepping (advection + projection every step) must not distort it: within 2% of the single
  // impulsive projection on the same mesh.
  EXPECT_NEAR(fine.measured / fine.impulsive, 1.0, 0.02);
  EXPECT_LE(fine.max_div_scaled, 1e-8);
}

}  // namespace
}  // namespace tetfsi::fluid
