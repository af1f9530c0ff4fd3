// Hard cases: a soft body dropped on a floor at h = 1/30 s stays bounded (energy never
// exceeds the initial total by more than 1%); an element squashed through itself stops the run
// with a clear message under StVK and recovers under the stable neo-Hookean law; contact
// keeps nodes above the floor and Coulomb friction stops a sliding block near v^2 / (2 mu g).
#include <gtest/gtest.h>

#include <cstdlib>

#include "mesh/structured_box.hpp"
#include "solid/integrator/trapezoidal.hpp"
#include "solid/solid_error.hpp"
#include "solid/tet/tet_model.hpp"

using namespace tetfsi;
using namespace tetfsi::solid;

namespace {

mesh::TetMesh unit_tet() {
  mesh::TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  return m;
}

TetMaterial soft(ConstitutiveLaw law) {
  TetMaterial mat;
  mat.youngs_modulus = 2e4;
  mat.poisson_ratio = 0.3;
  mat.density = 1000;
  mat.law = law;
  return mat;
}

double min_z(const TrapezoidalIntegrator& integ) {
  const Eigen::VectorXd x = integ.positions();
  double z = 1e300;
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) z = std::min(z, x[3 * v + 2]);
  return z;
}

}  // namespace

TEST(SolidRobustness, SoftBodyDroppedOnFloorStaysBounded) {
  // 0.2 m cube, 4^3 cells (384 tets), dropped from 0.5 m (impact at 3.1 m/s: the body moves
  // half its size per step); E = 20 kPa: its highest mode has omega h ~ 10 at h = 1/30 s.
  const auto mesh = mesh::structured_box({-0.1, -0.1, 0.5}, {0.1, 0.1, 0.7}, 4, 4, 4);
  // The StVK body is 5x stiffer: at 20 kPa its bottom layer inverts on impact (it then stops
  // with a SolidError, see the squash tests below).
  for (auto law : {ConstitutiveLaw::kStableNeoHookean, ConstitutiveLaw::kStVK}) {
    TetModelOptions options;
    options.project_spd = true;
    TetMaterial mat = soft(law);
    if (law == ConstitutiveLaw::kStVK) mat.youngs_modulus = 1e5;
    TetModel model(mesh, mat, options);
    TrapezoidalSettings settings;
    settings.time_step = 1.0 / 30.0;
    settings.gravity = {0, 0, -9.81};
    settings.rayleigh_beta = 0.002;
    TrapezoidalIntegrator integ(model, settings);
    integ.obstacles().add_plane({Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()});
    const double e0 = integ.energies().total();
    double worst = -1e300;
    for (int n = 0; n < 90; ++n) {  // 3 s: fall, impact, settle
      const auto& st = integ.step();
      worst = std::max(worst, st.total());
      if (std::getenv("TETFSI_VERBOSE"))
        std::printf("%d t=%.3f K=%.3f W=%.3f G=%.3f total=%.3f contacts=%d inv=%d minz=%.4f\n", n, st.time, st.kinetic,
                    st.strain, st.gravity_potential, st.total(), st.contacts, st.inverted, min_z(integ));
      EXPECT_GT(min_z(integ), -1e-12) << "step " << n;
    }
    EXPECT_LT(worst, e0 * 1.01) << "law " << static_cast<int>(law);
    // Resting on the floor at the end, and not exploded.
    EXPECT_LT(min_z(integ), 1e-3);
    EXPECT_LT(integ.displacement().cwiseAbs().maxCoeff(), 0.8);
  }
}

TEST(SolidRobustness, InvertedStVKElementStopsWithClearMessage) {
  TetModel model(unit_tet(), soft(ConstitutiveLaw::kStVK));
  TrapezoidalSettings settings;
  settings.time_step = 1.0 / 30.0;
  TrapezoidalIntegrator integ(model, settings);
  integ.fix_nodes({0, 1, 2});
  Eigen::VectorXd u = Eigen::VectorXd::Zero(12);
  u[11] = -45.0;  // apex moves ~1.5 m down in the first step: through the base
  integ.set_velocity(u);
  integ.step();
  try {
    integ.step();
    FAIL() << "an inverted StVK element did not stop the run";
  } catch (const SolidError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("step 2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("tet 0"), std::string::npos) << msg;
    EXPECT_NE(msg.find("inverted"), std::string::npos) << msg;
  }
}

TEST(SolidRobustness, InvertedNeoHookeanElementRecovers) {
  TetModel model(unit_tet(), soft(ConstitutiveLaw::kStableNeoHookean));
  TrapezoidalSettings settings;
  settings.time_step = 1.0 / 30.0;
  settings.rayleigh_beta = 0.05;
  TrapezoidalIntegrator integ(model, settings);
  integ.fix_nodes({0, 1, 2});
  Eigen::VectorXd u = Eigen::VectorXd::Zero(12);
  u[11] = -45.0;
  integ.set_velocity(u);
  const double e0 = integ.energies().total();
  int inverted_steps = 0;
  for (int n = 0; n < 300; ++n) {
    const auto& st = integ.step();
    inverted_steps += st.inverted > 0;
    EXPECT_LE(st.total(), e0 * 1.01) << "step " << n;
  }
  EXPECT_GT(inverted_steps, 0);  // it really was inverted
  EXPECT_GT(model.volume_ratios(integ.displacement())[0], 0.5);  // and came back
  EXPECT_LT(integ.velocity().norm(), 0.1 * 45.0);
}

TEST(SolidRobustness, FrictionStopsSlidingBlockNearCoulombDistance) {
  // Stiff small block sliding on the floor at v0 = 1 m/s, mu = 0.5: s = v0^2 / (2 mu g).
  const auto mesh = mesh::structured_box({0, 0, 0}, {0.1, 0.1, 0.05}, 2, 2, 1);
  TetMaterial mat = soft(ConstitutiveLaw::kStableNeoHookean);
  mat.youngs_modulus = 1e6;
  TetModel model(mesh, mat);
  TrapezoidalSettings settings;
  settings.time_step = 1e-3;
  settings.gravity = {0, 0, -9.81};
  settings.rayleigh_beta = 1e-3;
  TrapezoidalIntegrator integ(model, settings);
  integ.obstacles().add_plane({Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()});
  integ.obstacles().set_friction(0.5);
  integ.set_uniform_velocity({1, 0, 0});
  for (int n = 0; n < 400; ++n) integ.step();
  const double slid = integ.displacement()[0];
  const double expected = 1.0 / (2 * 0.5 * 9.81);
  std::printf("slid %.4f m, Coulomb %.4f m\n", slid, expected);
  EXPECT_NEAR(slid, expected, 0.10 * expected);
  EXPECT_GT(min_z(integ), -1e-12);
}

TEST(SolidRobustness, BadSettingsAreRejected) {
  TetModel model(unit_tet(), soft(ConstitutiveLaw::kStVK));
  TrapezoidalSettings settings;
  settings.time_step = 0;
  EXPECT_THROW(TrapezoidalIntegrator(model, settings), SolidError);
  settings.time_step = 0.01;
  TrapezoidalIntegrator integ(model, settings);
  EXPECT_THROW(integ.fix_nodes({7}), SolidError);
  EXPECT_THROW(integ.set_external_forces(Eigen::VectorXd::Constant(12, std::nan(""))), SolidError);
  EXPECT_THROW(integ.obstacles().add_plane({Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}), SolidError);
  EXPECT_THROW(integ.obstacles().add_box({Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero()}), SolidError);
}
