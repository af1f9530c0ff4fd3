// Element-level checks of the Total Lagrangian hex8 (solid/hex/hex8_element.hpp):
// consistent tangent, internal force = energy gradient, objectivity, patch test.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <tbb/global_control.h>
#include <random>

#include "solid/hex/block_mesh.hpp"
#include "solid/hex/hex8_element.hpp"
#include "solid/hex/hex_model.hpp"
#include "tests/hex/hex_test_states.hpp"

using namespace tetfsi::solid::hex;
using tetfsi::solid::hex::testing::distorted_hex;
using tetfsi::solid::hex::testing::random_displacement;

namespace {

Material make_material(MaterialLaw law) {
  Material m;
  m.law = law;
  m.youngs_modulus = 2.0e6;
  m.poisson_ratio = 0.3;
  m.density = 1000.0;
  return m;
}


}  // namespace

// K_T = K_L + K_NL must be the derivative of F_int: central differences, 1e-6 relative.
TEST(Hex8Element, TangentMatchesFiniteDifferenceOfInternalForce) {
  std::mt19937 rng(7);
  for (auto law : {MaterialLaw::kStVK, MaterialLaw::kNeoHookeanBonetWood}) {
    const Material m = make_material(law);
    for (int trial = 0; trial < 5; ++trial) {
      const Matrix83d X = distorted_hex(rng);
      const Matrix83d u = random_displacement(rng, X);
      Vector24d f;
      Matrix24d K;
      ASSERT_EQ(hex8_evaluate(m, X, u, &f, &K, nullptr), ElementStatus::Ok);
      const double h = 1e-6;
      Matrix24d fd;
      for (int j = 0; j < 24; ++j) {
        Matrix83d up = u, um = u;
        up(j / 3, j % 3) += h;
        um(j / 3, j % 3) -= h;
        Vector24d fp, fm;
        ASSERT_EQ(hex8_evaluate(m, X, up, &fp, nullptr, nullptr), ElementStatus::Ok);
        ASSERT_EQ(hex8_evaluate(m, X, um, &fm, nullptr, nullptr), ElementStatus::Ok);
        fd.col(j) = (fp - fm) / (2 * h);
      }
      const double rel = (K - fd).norm() / K.norm();
      EXPECT_LT(rel, 1e-6) << "law " << static_cast<int>(law) << " trial " << trial;
      EXPECT_LT((K - K.transpose()).norm() / K.norm(), 1e-13);
    }
  }
}

// F_int must be the gradient of the strain energy (so that K_T is the energy's Hessian).
TEST(Hex8Element, InternalForceIsEnergyGradient) {
  std::mt19937 rng(11);
  for (auto law : {MaterialLaw::kStVK, MaterialLaw::kNeoHookeanBonetWood}) {
    const Material m = make_material(law);
    const Matrix83d X = distorted_hex(rng);
    const Matrix83d u = random_displacement(rng, X);
    Vector24d f;
    ASSERT_EQ(hex8_evaluate(m, X, u, &f, nullptr, nullptr), ElementStatus::Ok);
    Vector24d fd;
    const double h = 1e-6;
    for (int j = 0; j < 24; ++j) {
      Matrix83d up = u, um = u;
      up(j / 3, j % 3) += h;
      um(j / 3, j % 3) -= h;
      double wp = 0, wm = 0;
      hex8_evaluate(m, X, up, nullptr, nullptr, &wp);
      hex8_evaluate(m, X, um, nullptr, nullptr, &wm);
      fd(j) = (wp - wm) / (2 * h);
    }
    EXPECT_LT((f - fd).norm() / f.norm(), 1e-6);
  }
}

// The assembled K_T of a distorted 2x2x2 block against finite differences of the assembled F_int.
TEST(HexModel, AssembledTangentMatchesFiniteDifference) {
  auto mesh = block_mesh({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  for (auto& p : mesh.vertices) p += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  const HexModel model(mesh, make_material(MaterialLaw::kNeoHookeanBonetWood));
  Eigen::VectorXd d(3 * model.num_nodes());
  for (int i = 0; i < d.size(); ++i) d(i) = 0.5 * jitter(rng);
  Eigen::VectorXd f;
  tetfsi::solid::SparseMatrix K;
  ASSERT_TRUE(model.evaluate(d, f, &K));
  const Eigen::MatrixXd Kd(K);
  Eigen::MatrixXd fd(d.size(), d.size());
  const double h = 1e-6;
  for (int j = 0; j < d.size(); ++j) {
    Eigen::VectorXd dp = d, dm = d, fp, fm;
    dp(j) += h;
    dm(j) -= h;
    ASSERT_TRUE(model.evaluate(dp, fp, nullptr));
    ASSERT_TRUE(model.evaluate(dm, fm, nullptr));
    fd.col(j) = (fp - fm) / (2 * h);
  }
  EXPECT_LT((Kd - fd).norm() / Kd.norm(), 1e-6);
  // Row-sum lumped masses are positive and add up to rho V; the jitter keeps the volume 1 only
  // approximately, so compare with the undeformed unit block loosely.
  EXPECT_GT(model.lumped_masses().minCoeff(), 0.0);
  EXPECT_NEAR(model.lumped_masses().sum(), 1000.0, 60.0);
}

// Objectivity: a rigid rotation of the undeformed body gives zero internal force, and rotating a
// deformed state rotates its internal forces (f(R x) = R f(x)), to round-off.
TEST(Hex8Element, RigidRotationGivesNoInternalForce) {
  std::mt19937 rng(5);
  for (auto law : {MaterialLaw::kStVK, MaterialLaw::kNeoHookeanBonetWood}) {
    const Material m = make_material(law);
    const Matrix83d X = distorted_hex(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(1.3, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
    const Matrix83d u = X * R.transpose() - X + Matrix83d::Constant(0.7);
    Vector24d f;
    ASSERT_EQ(hex8_evaluate(m, X, u, &f, nullptr, nullptr), ElementStatus::Ok);
    const double scale = m.youngs_modulus * 1.0;  // E * (element size)^2 [N]
    EXPECT_LT(f.cwiseAbs().maxCoeff() / scale, 1e-13) << "law " << static_cast<int>(law);

    const Matrix83d u1 = random_displacement(rng, X);
    const Matrix83d x1 = X + u1;
    Vector24d f1, f2;
    ASSERT_EQ(hex8_evaluate(m, X, u1, &f1, nullptr, nullptr), ElementStatus::Ok);
    ASSERT_EQ(hex8_evaluate(m, X, Matrix83d(x1 * R.transpose() - X), &f2, nullptr, nullptr), ElementStatus::Ok);
    for (int a = 0; a < 8; ++a) {
      EXPECT_LT((f2.segment<3>(3 * a) - R * f1.segment<3>(3 * a)).norm() / f1.norm(), 1e-12);
    }
  }
}

// Patch test: a linear displacement field u = A X + b on distorted hexes gives the exact constant
// stress S = lambda tr(E) I + 2 mu E, E = (A + A^T + A^T A)/2, at every Gauss point, and the
// interior nodes are in equilibrium (zero internal force), to 1e-10.
TEST(Hex8Element, PatchTestConstantStrainOnDistortedHexes) {
  auto mesh = block_mesh({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  mesh.vertices[13] += Eigen::Vector3d(0.12, -0.09, 0.07);  // the centre node (1,1,1)
  mesh.vertices[4] += Eigen::Vector3d(0.05, 0.1, 0.0);      // a face-interior node (bottom face)
  const Material m = make_material(MaterialLaw::kStVK);
  const HexModel model(mesh, m);
  Eigen::Matrix3d A;
  A << 0.05, -0.02, 0.03, 0.01, -0.04, 0.02, 0.03, 0.015, 0.06;
  const Eigen::Vector3d b(0.01, -0.02, 0.005);
  Eigen::VectorXd d(3 * model.num_nodes());
  for (int i = 0; i < model.num_nodes(); ++i) d.segment<3>(3 * i) = A * mesh.vertices[i] + b;
  const Eigen::Matrix3d E = 0.5 * (A + A.transpose() + A.transpose() * A);
  const Eigen::Matrix3d S_exact = m.lame_lambda() * E.trace() * Eigen::Matrix3d::Identity() + 2 * m.lame_mu() * E;
  std::vector<double> cauchy, pk2;
  model.element_stresses(d, cauchy, pk2);
  for (int e = 0; e < mesh.num_hexes(); ++e) {
    for (int v = 0; v < 6; ++v) {
      EXPECT_NEAR(pk2[6 * e + v], S_exact(kVoigt[v][0], kVoigt[v][1]), 1e-10 * S_exact.norm());
    }
  }
  Eigen::VectorXd f;
  ASSERT_TRUE(model.evaluate(d, f, nullptr));
  EXPECT_LT(f.segment<3>(3 * 13).norm(), 1e-10 * f.norm());
}

// Coloured assembly: F_int and K_T are bitwise the same on 1 and 2 threads.
TEST(HexModel, AssemblyIsBitwiseIndependentOfThreadCount) {
  auto mesh = block_mesh({0, 0, 0}, {1, 1, 1}, 6, 5, 4);
  const HexModel model(mesh, make_material(MaterialLaw::kStVK));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> dist(-0.02, 0.02);
  Eigen::VectorXd d(3 * model.num_nodes());
  for (int i = 0; i < d.size(); ++i) d(i) = dist(rng);
  Eigen::VectorXd f[2];
  tetfsi::solid::SparseMatrix K[2];
  for (int t = 1; t <= 2; ++t) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, t);
    ASSERT_TRUE(model.evaluate(d, f[t - 1], &K[t - 1]));
  }
  EXPECT_EQ((f[0] - f[1]).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_EQ(K[0].nonZeros(), K[1].nonZeros());  // same pattern (the model's), compare the values
  for (Eigen::Index k = 0; k < K[0].nonZeros(); ++k) ASSERT_EQ(K[0].valuePtr()[k], K[1].valuePtr()[k]) << k;
}
