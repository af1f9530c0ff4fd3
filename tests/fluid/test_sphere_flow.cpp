// Sphere cases on CGAL complex meshes (mesh::build_complex):
//  - potential flow past a fixed sphere (benchmarks.md sec. 4.4): one projection of a uniform flow;
//    surface C_p against 1 - (9/4) sin^2(theta).
//  - added mass of an oscillating sphere: prescribed x(t) = A sin(w t); pressure force = -1/2 rho V x''
//    (benchmarks.md sec. 2.1).
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

TEST(FluidSphere, PotentialFlowSurfacePressureCoefficient) {
  const validation::PotentialFlowResult coarse = validation::potential_flow(0.5, 1.0, 0.14, 0.25);
  const validation::PotentialFlowResult fine = validation::potential_flow(0.5, 1.0, 0.09, 0.2);
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
  for (auto scheme : {AdvectionScheme::kSemiLagrangian, AdvectionScheme::kBfecc, AdvectionScheme::kLinear}) {
  const validation::AddedMassResult r = validation::added_mass(0.5, 1.0, 0.12, 0.25, 40, scheme);
  std::printf("added mass: %d tets: measured %.5f kg (impulsive start %.5f kg), 1/2 rho V = %.5f kg: rel. error %.4f; max|div| h/U %.1e\n",
              r.tets, r.measured, r.impulsive, r.ideal, r.measured / r.ideal - 1.0, r.max_div_scaled);
  // CI-sized band (the benchmark checks 5% at a finer mesh): 10%.
  EXPECT_NEAR(r.measured / r.ideal, 1.0, 0.10);
  EXPECT_LE(r.max_div_scaled, 1e-8);
  }
}

}  // namespace
}  // namespace tetfsi::fluid
