// A solid's FEM mesh is its subdomain's tets of the shared complex, with maps back to it.
#include <gtest/gtest.h>

#include "mesh/structured_box.hpp"
#include "mesh/submesh.hpp"

using namespace tetfsi::mesh;

TEST(Submesh, ExtractSubdomainKeepsTheSolidAndMapsBack) {
  auto m = structured_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2, kFluidSubdomain);
  int solid_tets = 0;
  for (int t = 0; t < m.num_tets(); ++t)
    if (t % 6 == 0) m.subdomain[t] = solid_subdomain(0), ++solid_tets;
  const auto sub = extract_subdomain(m, solid_subdomain(0));
  ASSERT_EQ(sub.mesh.num_tets(), solid_tets);
  double volume = 0, expected = 0;
  for (int t = 0; t < sub.mesh.num_tets(); ++t) {
    volume += signed_volume(sub.mesh, t);
    expected += signed_volume(m, sub.to_parent_tet[t]);
    for (int i = 0; i < 4; ++i)
      EXPECT_EQ(sub.to_parent_vertex[sub.mesh.tets[t][i]], m.tets[sub.to_parent_tet[t]][i]);
  }
  EXPECT_NEAR(volume, expected, 1e-15);
  EXPECT_THROW(extract_subdomain(m, solid_subdomain(1)), std::invalid_argument);
}

