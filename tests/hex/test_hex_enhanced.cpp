// The enhanced hex8 (solid/hex/hex8_enhanced.hpp): condensed tangent = derivative of the condensed
// force, force = energy gradient, objectivity, and the MacNeal & Harder 1985 patch test on their
// 7-element mesh (both formulations), small and finite homogeneous deformation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "mesh/hex_volume_mesh.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/hex8_enhanced.hpp"
#include "solid/hex/hex_model.hpp"
#include "tests/hex/macneal_harder_mesh.hpp"
#include "tests/hex/hex_test_states.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::hex;
using tetfsi::solid::hex::testing::distorted_hex;
using tetfsi::solid::hex::testing::random_displacement;

namespace {

Material make_material(MaterialLaw law) {
  Material m;
  m.law = law;
  m.youngs_modulus = 2.0e6;
  m.poisson_ratio = 0.3;
  return m;
}


}  // namespace

// The condensed K_T must be dF_int/du with the modes re-solved at each perturbed u (central
// differences, h = 1e-6: truncation ~ h^2 |f'''| ~ 1e-12 relative, round-off ~ 1e-16/h = 1e-10),
// and F_int must be dW/du: 1e-6 relative, both laws, at finite strain.
TEST(Hex8Enhanced, CondensedTangentAndForceAreDerivatives) {
  std::mt19937 rng(11);
  for (auto law : {MaterialLaw::kStVK, MaterialLaw::kNeoHookeanBonetWood}) {
    const Material m = make_material(law);
    for (int trial = 0; trial < 4; ++trial) {
      const Matrix83d X = distorted_hex(rng);
      const Matrix83d u = random_displacement(rng, X);
      Vector24d f;
      Matrix24d K;
      Eigen::Matrix3d alpha;
      ASSERT_EQ(hex8_enhanced_evaluate(m, X, u, &f, &K, nullptr, &alpha), ElementStatus::Ok);
      EXPECT_GT(alpha.norm(), 1e-3);  // the modes are active
      const double h = 1e-6;
      Matrix24d fd;
      Vector24d fw;
      for (int j = 0; j < 24; ++j) {
        Matrix83d up = u, um = u;
        up(j / 3, j % 3) += h;
        um(j / 3, j % 3) -= h;
        Vector24d fp, fm;
        double wp = 0, wm = 0;
        ASSERT_EQ(hex8_enhanced_evaluate(m, X, up, &fp, nullptr, &wp), ElementStatus::Ok);
        ASSERT_EQ(hex8_enhanced_evaluate(m, X, um, &fm, nullptr, &wm), ElementStatus::Ok);
        fd.col(j) = (fp - fm) / (2 * h);
        fw(j) = (wp - wm) / (2 * h);
      }
      EXPECT_LE((K - fd).norm(), 1e-6 * K.norm()) << "law " << static_cast<int>(law) << " trial " << trial;
      EXPECT_LE((f - fw).norm(), 1e-6 * f.norm());
      EXPECT_LE((K - K.transpose()).norm(), 1e-12 * K.norm());
    }
  }
}

// A rigid rotation u = (R - I) X: F = R with alpha = 0 solves the modes' equations, so the
// element carries no force (< 1e-13 E h^2) and no mode.
TEST(Hex8Enhanced, RigidRotationLeavesNoForce) {
  std::mt19937 rng(3);
  const Material m = make_material(MaterialLaw::kNeoHookeanBonetWood);
  const Matrix83d X = distorted_hex(rng);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const Matrix83d u = X * R.transpose() - X;
  Vector24d f;
  Eigen::Matrix3d alpha;
  ASSERT_EQ(hex8_enhanced_evaluate(m, X, u, &f, nullptr, nullptr, &alpha), ElementStatus::Ok);
  EXPECT_LE(f.cwiseAbs().maxCoeff(), 1e-13 * m.youngs_modulus);
  EXPECT_LE(alpha.cwiseAbs().maxCoeff(), 1e-13);
}

// The MacNeal-Harder mesh has a negative corner Jacobian (hex 3, corner 4: -0.01265) but a
// positive Jacobian at every Gauss point: accepted, as by other codes.
TEST(MacNealHarder, StandardMeshIsAccepted) {
  tetfsi::mesh::HexMesh m = tetfsi::test::macneal_harder_mesh();
  const auto& h = m.hexes[3];
  const auto& n = tetfsi::mesh::kHexCornerNeighbours[4];
  Eigen::Matrix3d J;
  J << m.vertices[h[n[0]]] - m.vertices[h[4]], m.vertices[h[n[1]]] - m.vertices[h[4]],
      m.vertices[h[n[2]]] - m.vertices[h[4]];
  EXPECT_NEAR(J.determinant(), -0.01265, 1e-5);
  std::vector<std::string> warnings;
  EXPECT_NO_THROW(tetfsi::mesh::check_hex_volume_mesh(m, "macneal_harder", warnings));
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(m.hexes, tetfsi::test::macneal_harder_mesh().hexes);
}

namespace {

// Patch test: u = (F - I) X on the 8 cube corners, the 8 interior nodes free (static Newton,
// `steps` load steps). Exact solution: u = (F - I) X everywhere, S = S(F) in every element.
void patch_test(Hex8Formulation formulation, const Eigen::Matrix3d& F, int steps) {
  const tetfsi::mesh::HexMesh mesh = tetfsi::test::macneal_harder_mesh();
  const Material mat = make_material(MaterialLaw::kNeoHookeanBonetWood);
  const HexModel model(mesh, mat, formulation);
  BoundaryConditions bc;
  for (int v = 0; v < 8; ++v)
    for (int k = 0; k < 3; ++k) bc.prescribed.emplace_back(3 * v + k, ((F - Eigen::Matrix3d::Identity()) * mesh.vertices[v])(k));
  StaticOptions opt;
  opt.load_steps = steps;
  opt.residual_tolerance = 1e-13;
  opt.increment_tolerance = 1e-14;
  const StaticResult r = solve_static(model, bc, opt);
  double umax = 0, err = 0;
  for (int v = 8; v < 16; ++v) {
    const Eigen::Vector3d exact = (F - Eigen::Matrix3d::Identity()) * mesh.vertices[v];
    umax = std::max(umax, exact.norm());
    err = std::max(err, (r.displacement.segment<3>(3 * v) - exact).norm());
  }
  EXPECT_LE(err, 1e-10 * umax);
  Eigen::Matrix3d S;
  ASSERT_TRUE(evaluate_material(mat, F, S, nullptr, nullptr));
  std::vector<double> cauchy, pk2;
  model.element_stresses(r.displacement, cauchy, pk2);
  double serr = 0;
  for (int e = 0; e < 7; ++e)
    for (int v = 0; v < 6; ++v) serr = std::max(serr, std::abs(pk2[6 * e + v] - S(kVoigt[v][0], kVoigt[v][1])));
  EXPECT_LE(serr, 1e-6 * S.norm());
  std::printf("patch %s |F - I| %.1e: max displacement error %.2e of %.2e m, max S error %.2e of |S| %.2e Pa\n",
              formulation == Hex8Formulation::Enhanced ? "enhanced" : "standard", (F - Eigen::Matrix3d::Identity()).norm(),
              err, umax, serr, S.norm());
}

Eigen::Matrix3d homogeneous(double scale) {
  Eigen::Matrix3d G;
  G << 0.8, 0.3, -0.2, 0.1, -0.5, 0.4, 0.25, -0.15, 0.6;
  return Eigen::Matrix3d::Identity() + scale * G;
}

}  // namespace

TEST(MacNealHarder, PatchTestSmallStrain) {
  for (auto f : {Hex8Formulation::Standard, Hex8Formulation::Enhanced}) patch_test(f, homogeneous(1e-4), 1);
}

TEST(MacNealHarder, PatchTestFiniteStrain) {
  for (auto f : {Hex8Formulation::Standard, Hex8Formulation::Enhanced}) patch_test(f, homogeneous(0.4), 4);
}
