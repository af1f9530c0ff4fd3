// Element-level checks of the constant-strain tet: analytic StVK / neo-Hookean stress in a
// uniaxial stretch, K' against finite differences of K(d), K against the energy gradient,
// lumped mass, rigid-motion invariance, deterministic parallel assembly, bad input.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "mesh/structured_box.hpp"
#include "solid/assembly/block_assembler.hpp"
#include "solid/solid_error.hpp"
#include "solid/tet/constitutive.hpp"
#include "solid/tet/tet_model.hpp"
#include "tests/solid/solid_fixtures.hpp"

using namespace tetfsi;
using namespace tetfsi::solid;

namespace {

using test::unit_tet;

TetMaterial material(ConstitutiveLaw law) { return test::tet_material(law, 1e6); }

Eigen::VectorXd random_displacement(int n, double scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-scale, scale);
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) d[i] = dist(rng);
  return d;
}

double relative_fd_error_of_tangent(const TetModel& model, const Eigen::VectorXd& d) {
  Eigen::VectorXd f;
  SparseMatrix K;
  EXPECT_TRUE(model.evaluate(d, f, &K));
  const Eigen::MatrixXd Kd = Eigen::MatrixXd(K);
  Eigen::MatrixXd Kfd(d.size(), d.size());
  const double eps = 1e-6 * (1.0 + d.cwiseAbs().maxCoeff());
  for (Eigen::Index j = 0; j < d.size(); ++j) {
    Eigen::VectorXd dp = d, dm = d, fp, fm;
    dp[j] += eps;
    dm[j] -= eps;
    model.evaluate(dp, fp, nullptr);
    model.evaluate(dm, fm, nullptr);
    Kfd.col(j) = (fp - fm) / (2 * eps);
  }
  return (Kfd - Kd).norm() / Kd.norm();
}

}  // namespace

// Uniaxial stretch F = diag(s, 1, 1): E11 = (s^2 - 1)/2, S11 = (lambda + 2 mu) E11,
// S22 = S33 = lambda E11, P = F S; nodal force on vertex 1 (g_1 = e_x) is V P e_x.
TEST(TetElement, StVKStretchMatchesAnalyticStress) {
  const auto mat = material(ConstitutiveLaw::kStVK);
  TetModel model(unit_tet(), mat);
  const double s = 1.2, lambda = mat.lambda(), mu = mat.mu(), V = 1.0 / 6.0;
  Eigen::VectorXd d = Eigen::VectorXd::Zero(12);
  for (int v = 0; v < 4; ++v) d[3 * v] = (s - 1) * model.reference_positions()[3 * v];
  const Eigen::Matrix3d F = model.deformation_gradient(d, 0);
  EXPECT_NEAR((F - Eigen::Vector3d(s, 1, 1).asDiagonal().toDenseMatrix()).norm(), 0, 1e-14);

  const double E11 = 0.5 * (s * s - 1);
  const double P11 = s * (lambda + 2 * mu) * E11, P22 = lambda * E11;
  const Eigen::Matrix3d P = first_piola(ConstitutiveParams::from(mat), F);
  EXPECT_NEAR(P(0, 0), P11, 1e-12 * P11);
  EXPECT_NEAR(P(1, 1), P22, 1e-12 * P11);
  EXPECT_NEAR(P(2, 2), P22, 1e-12 * P11);
  EXPECT_NEAR(P(0, 1), 0, 1e-12 * P11);

  Eigen::VectorXd f;
  ASSERT_TRUE(model.evaluate(d, f, nullptr));
  EXPECT_NEAR(f[3], V * P11, 1e-12 * V * P11);  // vertex 1, x
  EXPECT_NEAR(f.segment<3>(0).x(), -V * P11, 1e-12 * V * P11);
  EXPECT_NEAR(f.sum(), 0, 1e-9);  // equilibrium of the element forces
  const double W = V * (0.5 * lambda * E11 * E11 + mu * E11 * E11);
  EXPECT_NEAR(model.strain_energy(d), W, 1e-12 * W);
  // Cauchy stress sigma = P F^T / J: sigma11 = P11 s / s.
  EXPECT_NEAR(model.cauchy_stresses(d)(0, 0), P11, 1e-9 * P11);
}

// Stable neo-Hookean, same stretch: P = mu F + lambda' (J - a) cof F, cof F = diag(1, s, s).
TEST(TetElement, StableNeoHookeanStretchMatchesAnalyticStress) {
  const auto mat = material(ConstitutiveLaw::kNeoHookeanStable);
  const double s = 1.2, lp = mat.lambda() + mat.mu(), a = 1 + mat.mu() / lp;
  const Eigen::Matrix3d F = Eigen::Vector3d(s, 1, 1).asDiagonal();
  const Eigen::Matrix3d P = first_piola(ConstitutiveParams::from(mat), F);
  const double P11 = mat.mu() * s + lp * (s - a), P22 = mat.mu() + lp * (s - a) * s;
  EXPECT_NEAR(P(0, 0), P11, 1e-12 * std::abs(P11));
  EXPECT_NEAR(P(1, 1), P22, 1e-12 * std::abs(P11));
  // Rest state is stress free and the small-strain response equals StVK's.
  EXPECT_NEAR(first_piola(ConstitutiveParams::from(mat), Eigen::Matrix3d::Identity()).norm(), 0, 1e-9);
  const Eigen::Matrix3d dF = Eigen::Matrix3d::Random();
  const Eigen::Matrix3d dP_nh = first_piola_differential(ConstitutiveParams::from(mat), Eigen::Matrix3d::Identity(), dF);
  const Eigen::Matrix3d dP_stvk = first_piola_differential(ConstitutiveParams::from(material(ConstitutiveLaw::kStVK)),
                                                           Eigen::Matrix3d::Identity(), dF);
  EXPECT_NEAR((dP_nh - dP_stvk).norm(), 0, 1e-9 * dP_stvk.norm());
}

TEST(TetElement, TangentMatchesFiniteDifferences) {
  const auto mesh = mesh::structured_box({0, 0, 0}, {0.2, 0.1, 0.1}, 2, 1, 1);
  for (auto law : {ConstitutiveLaw::kStVK, ConstitutiveLaw::kNeoHookeanStable}) {
    TetModel model(mesh, material(law));
    const Eigen::VectorXd d = random_displacement(3 * model.num_nodes(), 0.01, 7);  // strains ~ 20%
    const double err = relative_fd_error_of_tangent(model, d);
    EXPECT_LT(err, 1e-6) << "law " << static_cast<int>(law);
  }
  // Inverted configuration, robust law: the tangent stays consistent.
  TetModel nh(unit_tet(), material(ConstitutiveLaw::kNeoHookeanStable));
  Eigen::VectorXd d = Eigen::VectorXd::Zero(12);
  d[11] = -1.5;  // apex through the base
  EXPECT_LT(relative_fd_error_of_tangent(nh, d), 1e-6);
}

TEST(TetElement, ForceIsEnergyGradient) {
  const auto mesh = mesh::structured_box({0, 0, 0}, {0.2, 0.1, 0.1}, 2, 1, 1);
  for (auto law : {ConstitutiveLaw::kStVK, ConstitutiveLaw::kNeoHookeanStable}) {
    TetModel model(mesh, material(law));
    const Eigen::VectorXd d = random_displacement(3 * model.num_nodes(), 0.01, 3);
    Eigen::VectorXd f;
    ASSERT_TRUE(model.evaluate(d, f, nullptr));
    Eigen::VectorXd g(d.size());
    const double eps = 1e-7;
    for (Eigen::Index j = 0; j < d.size(); ++j) {
      Eigen::VectorXd dp = d, dm = d;
      dp[j] += eps;
      dm[j] -= eps;
      g[j] = (model.strain_energy(dp) - model.strain_energy(dm)) / (2 * eps);
    }
    EXPECT_LT((g - f).norm() / f.norm(), 1e-6);
  }
}

TEST(TetElement, LumpedMassAndRigidMotions) {
  const auto mesh = mesh::structured_box({0, 0, 0}, {0.3, 0.2, 0.1}, 3, 2, 1);
  TetModel model(mesh, material(ConstitutiveLaw::kStVK));
  EXPECT_NEAR(model.lumped_masses().sum(), 1000 * 0.3 * 0.2 * 0.1, 1e-12);
  // A finite rigid rotation plus translation leaves K(d) = 0 (Green strain is invariant).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::VectorXd d(3 * model.num_nodes());
  for (int v = 0; v < model.num_nodes(); ++v) {
    const Eigen::Vector3d X = model.reference_positions().segment<3>(3 * v);
    d.segment<3>(3 * v) = R * X + Eigen::Vector3d(1, -2, 0.5) - X;
  }
  Eigen::VectorXd f;
  SparseMatrix K;
  ASSERT_TRUE(model.evaluate(d, f, &K));
  EXPECT_LT(f.norm(), 1e-9);
  EXPECT_LT(model.strain_energy(d), 1e-12);
  EXPECT_LT((Eigen::MatrixXd(K) - Eigen::MatrixXd(K).transpose()).norm(), 1e-9 * K.norm());
}

TEST(TetElement, ParallelAssemblyIsDeterministic) {
  const auto mesh = mesh::structured_box({0, 0, 0}, {1, 1, 1}, 6, 6, 6);
  TetModel model(mesh, material(ConstitutiveLaw::kStVK));
  const Eigen::VectorXd d = random_displacement(3 * model.num_nodes(), 0.01, 11);
  Eigen::VectorXd f1, f2;
  SparseMatrix K1, K2;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    ASSERT_TRUE(model.evaluate(d, f1, &K1));
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    ASSERT_TRUE(model.evaluate(d, f2, &K2));
  }
  ASSERT_EQ(K1.nonZeros(), K2.nonZeros());
  EXPECT_EQ(std::memcmp(K1.valuePtr(), K2.valuePtr(), sizeof(double) * K1.nonZeros()), 0);
  EXPECT_EQ(std::memcmp(f1.data(), f2.data(), sizeof(double) * f1.size()), 0);
}

TEST(TetElement, BadInputIsRejectedWithAClearError) {
  auto bad = material(ConstitutiveLaw::kStVK);
  bad.poisson_ratio = 0.5;
  EXPECT_THROW(TetModel(unit_tet(), bad), SolidError);
  auto flat = unit_tet();
  flat.vertices[3] = {0.3, 0.3, 0};  // zero volume
  try {
    TetModel model(flat, material(ConstitutiveLaw::kStVK));
    FAIL() << "degenerate tet accepted";
  } catch (const SolidError& e) {
    EXPECT_NE(std::string(e.what()).find("tet 0"), std::string::npos) << e.what();
  }
  TetModel model(unit_tet(), material(ConstitutiveLaw::kStVK));
  Eigen::VectorXd d = Eigen::VectorXd::Zero(12), f;
  d[5] = std::nan("");
  EXPECT_FALSE(model.evaluate(d, f, nullptr));
  EXPECT_NE(model.last_error().find("non-finite"), std::string::npos) << model.last_error();
}

TEST(TetElement, TangentMatrixMatchesDirectionalDerivative) {
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + 0.3 * Eigen::Matrix3d::Random();
  for (auto law : {ConstitutiveLaw::kStVK, ConstitutiveLaw::kNeoHookeanStable}) {
    const auto p = ConstitutiveParams::from(material(law));
    const Eigen::Matrix<double, 9, 9> C = first_piola_tangent(p, F);
    for (int k = 0; k < 9; ++k) {
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF(k % 3, k / 3) = 1.0;
      const Eigen::Matrix3d dP = first_piola_differential(p, F, dF);
      EXPECT_LT((C.col(k) - dP.reshaped()).norm(), 1e-12 * C.norm());
    }
  }
}

TEST(BlockAssembler, ElementMatricesSummedRangeByRangeEqualOneSumBitForBit) {
  // TetModel sums its element matrices into the tangent 8,192 tets at a time; every entry must be
  // the same floating-point sum as one pass over all elements. Random element matrices on a box of
  // 4 x 3 x 3 cells (tets of a node in several ranges), ranges of 7 elements against one range.
  const mesh::TetMesh box = mesh::structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d(4, 3, 3), 4, 3, 3);
  std::vector<int> flat;
  for (const auto& t : box.tets) flat.insert(flat.end(), t.begin(), t.end());
  const solid::BlockAssembler assembler(box.num_vertices(), 4, flat);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> ke(static_cast<std::size_t>(assembler.num_elements()) * 144);
  for (double& k : ke) k = value(rng);
  Eigen::SparseMatrix<double> whole, ranged;
  assembler.add_element_matrices(ke.data(), 0, assembler.num_elements(), whole);
  ranged = whole;
  ranged.coeffs().setConstant(42.0);  // first == 0 must start from zero, whatever out held
  for (int first = 0; first < assembler.num_elements(); first += 7) {
    const int end = std::min(assembler.num_elements(), first + 7);
    assembler.add_element_matrices(ke.data() + static_cast<std::size_t>(first) * 144, first, end, ranged);
  }
  ASSERT_EQ(ranged.nonZeros(), whole.nonZeros());
  EXPECT_TRUE(std::equal(whole.innerIndexPtr(), whole.innerIndexPtr() + whole.nonZeros(), ranged.innerIndexPtr()));
  for (Eigen::Index i = 0; i < whole.nonZeros(); ++i)
    ASSERT_EQ(ranged.valuePtr()[i], whole.valuePtr()[i]) << "entry " << i;
  // And the sum is the element matrices' sum: entry (0, 0) gathers K_e(3 i, 3 i) of node 0's tets.
  double diagonal = 0;
  for (int e = 0; e < assembler.num_elements(); ++e)
    for (int i = 0; i < 4; ++i)
      if (flat[4 * e + i] == 0) diagonal += ke[static_cast<std::size_t>(e) * 144 + (3 * i) * 12 + 3 * i];
  EXPECT_NEAR(whole.coeff(0, 0), diagonal, 1e-12);
  EXPECT_THROW(assembler.add_element_matrices(ke.data(), 0, assembler.num_elements() + 1, ranged), SolidError);
}
