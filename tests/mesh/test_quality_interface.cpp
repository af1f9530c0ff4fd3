// Quality measures against closed-form values, and the interface extraction on exact structured
// meshes whose interface is known face by face.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/quality.hpp"
#include "mesh/structured_box.hpp"

using namespace tetfsi::mesh;

namespace {

/// Relabels the tets of `m` whose centroid lies in [lo, hi] as `label`.
void label_block(TetMesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int label) {
  for (int t = 0; t < m.num_tets(); ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : m.tets[t]) c += m.vertices[v] / 4.0;
    if ((c.array() > lo.array()).all() && (c.array() < hi.array()).all()) m.subdomain[t] = label;
  }
}

}  // namespace

TEST(Quality, RegularTetrahedron) {
  const Eigen::Vector3d a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
  for (double angle : dihedral_angles_deg(a, b, c, d)) EXPECT_NEAR(angle, std::acos(1.0 / 3.0) * 180 / M_PI, 1e-10);
  EXPECT_NEAR(radius_edge_ratio(a, b, c, d), std::sqrt(6.0) / 4.0, 1e-12);
}

TEST(Quality, KuhnTetsOfTheStructuredBox) {
  // Every Kuhn tet of a cube has dihedral angles 45, 60 and 90 degrees; R = sqrt(3)/2 l, l_min = l.
  const TetMesh m = structured_box({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  const QualityReport q = quality_report(m);
  EXPECT_EQ(q.num_tets, 162);
  EXPECT_EQ(q.tets_per_subdomain.at(kFluidSubdomain), 162);
  EXPECT_NEAR(q.min_dihedral_deg, 45.0, 1e-9);
  EXPECT_NEAR(q.max_dihedral_deg, 90.0, 1e-9);
  EXPECT_NEAR(q.max_radius_edge, std::sqrt(3.0) / 2.0, 1e-9);
  EXPECT_EQ(q.inverted, 0);
  EXPECT_EQ(q.degenerate, 0);
  // Each Kuhn tet of a cell of size l has edges l, l, l, l sqrt2, l sqrt2, l sqrt3.
  EXPECT_NEAR(mean_edge_length(m, kFluidSubdomain), (3.0 + 2.0 * std::sqrt(2.0) + std::sqrt(3.0)) / 6.0 / 3.0, 1e-12);
}

TEST(Quality, InvertedAndDegenerateTetsAreCounted) {
  TetMesh m = structured_box({0, 0, 0}, {1, 1, 1}, 1, 1, 1);
  std::swap(m.tets[0][0], m.tets[0][1]);  // inverted
  m.vertices.push_back({0.5, 0.5, 0.0});
  m.tets.push_back({0, 1, 2, 8});  // vertices 0, 1, 2 and 8 all at z = 0: flat
  m.subdomain.push_back(kFluidSubdomain);
  const QualityReport q = quality_report(m);
  EXPECT_EQ(q.inverted, 1);
  EXPECT_EQ(q.degenerate, 1);
  EXPECT_EQ(q.num_tets, 7);
}

TEST(Quality, MinDihedralCheckEqualsTheFullReport) {
  // The per-step check of a moving mesh must agree exactly with quality_report on the fields it
  // computes: a jittered box (varied angles), one fluid tet inverted, one flat, a solid block
  // (excluded by the label), and a second thread count.
  TetMesh m = structured_box({0, 0, 0}, {1, 1, 1}, 6, 6, 6);
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    m.vertices[v] += 0.03 * Eigen::Vector3d(std::sin(7.0 * v), std::cos(11.0 * v), std::sin(13.0 * v + 1));
  label_block(m, {0.3, 0.3, 0.3}, {0.7, 0.7, 0.7}, solid_subdomain(0));
  std::swap(m.tets[0][0], m.tets[0][1]);
  m.vertices.push_back({0.5, 0.5, 0.0});
  m.tets.push_back({0, 1, 2, static_cast<int>(m.vertices.size()) - 1});
  m.vertices[1] = {1.0 / 6, 0, 0}, m.vertices[2] = {0, 1.0 / 6, 0}, m.vertices[0] = {0, 0, 0};
  m.subdomain.push_back(kFluidSubdomain);
  const QualityReport full = quality_report(m, kFluidSubdomain);
  const AngleCheck check = min_dihedral_check(m, kFluidSubdomain);
  EXPECT_GT(full.inverted + full.degenerate, 0);
  EXPECT_EQ(check.flat_or_inverted, full.inverted + full.degenerate);
  EXPECT_EQ(check.min_dihedral_deg, full.min_dihedral_deg);  // bit for bit: the same cosines
  EXPECT_LT(check.min_dihedral_deg, 45.0);                    // the jitter did change the angles
  const AngleCheck solid = min_dihedral_check(m, solid_subdomain(0));
  EXPECT_EQ(solid.min_dihedral_deg, quality_report(m, solid_subdomain(0)).min_dihedral_deg);
}

TEST(Interface, EmbeddedBlockHasItsSurfaceAsInterface) {
  TetMesh m = structured_box({0, 0, 0}, {4, 4, 4}, 4, 4, 4);
  label_block(m, {1, 1, 1}, {3, 3, 3}, solid_subdomain(0));
  const InterfaceCheck check = check_interface(m);
  EXPECT_TRUE(check.conforming()) << check.first_defect;
  EXPECT_EQ(check.interface_faces, 6 * 4 * 2);  // 6 sides x 4 cell faces x 2 triangles
  const auto faces = interface_faces(m);
  ASSERT_EQ(faces.size(), 48u);
  double area = 0.0;
  for (const auto& f : faces) {
    EXPECT_EQ(m.subdomain[f.solid_tet], solid_subdomain(0));
    EXPECT_EQ(m.subdomain[f.fluid_tet], kFluidSubdomain);
    EXPECT_EQ(f.solid_subdomain, solid_subdomain(0));
    const auto& x = m.vertices;
    const Eigen::Vector3d n = (x[f.vertices[1]] - x[f.vertices[0]]).cross(x[f.vertices[2]] - x[f.vertices[0]]);
    const Eigen::Vector3d centre = (x[f.vertices[0]] + x[f.vertices[1]] + x[f.vertices[2]]) / 3.0;
    EXPECT_GT(n.dot(centre - Eigen::Vector3d(2, 2, 2)), 0.0);  // out of the solid, into the fluid
    area += 0.5 * n.norm();
    // The local faces name the same triangle on both sides, and it is opposite the named vertex.
    for (const auto& [t, lf] : {std::pair{f.solid_tet, f.solid_face}, std::pair{f.fluid_tet, f.fluid_face}}) {
      for (int k = 0; k < 3; ++k) {
        const int v = m.tets[t][kTetFaceVertices[lf][k]];
        EXPECT_TRUE(v == f.vertices[0] || v == f.vertices[1] || v == f.vertices[2]);
      }
    }
    // The local face ordering gives the outward normal of the positively oriented solid tet.
    const Eigen::Vector3d opposite = x[m.tets[f.solid_tet][f.solid_face]];
    EXPECT_LT(n.dot(opposite - x[f.vertices[0]]), 0.0);
  }
  EXPECT_NEAR(area, 6 * 4.0, 1e-12);
}

TEST(Interface, DefectsAreReported) {
  // A solid touching the box boundary has faces with no fluid tet behind them.
  TetMesh touching = structured_box({0, 0, 0}, {4, 4, 4}, 4, 4, 4);
  label_block(touching, {-1, -1, -1}, {2, 2, 2}, solid_subdomain(0));
  EXPECT_EQ(check_interface(touching).exposed_solid_faces, 3 * 4 * 2);
  EXPECT_THROW(interface_faces(touching), MeshError);
  // Two solids in contact share faces without fluid between them.
  TetMesh contact = structured_box({0, 0, 0}, {4, 4, 4}, 4, 4, 4);
  label_block(contact, {1, 1, 1}, {2, 3, 3}, solid_subdomain(0));
  label_block(contact, {2, 1, 1}, {3, 3, 3}, solid_subdomain(1));
  const InterfaceCheck c = check_interface(contact);
  EXPECT_EQ(c.solid_solid_faces, 4 * 2);
  EXPECT_FALSE(c.conforming());
  // A face of three tets.
  TetMesh extra = structured_box({0, 0, 0}, {1, 1, 1}, 1, 1, 1);
  extra.vertices.push_back({2, 2, 2});
  const auto& t0 = extra.tets[0];
  extra.tets.push_back({t0[kTetFaceVertices[0][0]], t0[kTetFaceVertices[0][2]], t0[kTetFaceVertices[0][1]], 8});
  extra.subdomain.push_back(kFluidSubdomain);
  EXPECT_GE(check_interface(extra).overshared_faces + check_interface(extra).misoriented_faces, 1);
}
