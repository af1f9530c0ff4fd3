// Regression: a solid much smaller than the fluid box is meshed, not lost. CGAL seeds its
// refinement where rays from the box centre meet any surface, which can all be the box; the
// mesher seeds each solid itself (complex_mesher.cpp, seed_every_surface).
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"

using namespace tetfsi::mesh;

TEST(ComplexMesherSmallSolid, SphereOfAFifthOfTheBoxKeepsItsVolume) {
  for (double half_width : {0.5, 0.6, 1.0}) {
    const double r = 0.1;
    MeshSizing sizing;
    sizing.edge_length = 0.15;
    sizing.edge_length_near_solids = 0.025;
    sizing.grading_distance = 0.25;
    sizing.facet_distance = 0.0025;
    const Eigen::Vector3d h = Eigen::Vector3d::Constant(half_width);
    const TetMesh m = build_complex(-h, h, {make_sphere(r, 3)}, sizing);
    double solid = 0;
    for (int t = 0; t < m.num_tets(); ++t)
      if (m.subdomain[t] == solid_subdomain(0)) solid += signed_volume(m, t);
    const double exact = 4.0 / 3.0 * M_PI * r * r * r;
    // Chordal error of facets with sagitta <= facet_distance: volume within ~3 facet_distance / r.
    EXPECT_NEAR(solid, exact, 3 * sizing.facet_distance / r * exact) << "box half-width " << half_width;
  }
}
