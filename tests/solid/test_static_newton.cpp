// Exact Newton in statics (solid/analysis/static_solver.hpp): Cook's membrane of nonlinear tets,
// plane strain (Cook 1974; the finite-strain form of the deal.II code-gallery "Quasi-static
// finite-strain compressible elasticity"): the trapezoid (0, 0), (48, 44), (48, 60), (0, 44) mm,
// clamped at x = 0, a dead shear traction of 1 N per mm of thickness on the 16 mm end,
// mu = 0.4225 MPa, nu = 0.3, neo-Hookean (each law of solid/laws/hyperelastic_law.hpp). Mesh: 16 x 16
// cells mapped onto the trapezoid, one cell of 1 mm through the thickness, 6 tets per cell, u_z = 0.
//
// The tets' element tangent is projected to PSD in dynamics (TetModelOptions::project_spd, on here
// as in every neo-Hookean scene); the static solver must use the exact tangent wherever the system is
// positive definite, so Newton converges quadratically: at the last two iterations before the
// residual tolerance r_{k+1} / r_k <= 0.05, the estimated order of convergence at the last one is
// >= 1.8 (1 for a linear rate, 2 for Newton), and r_{k+1} / r_k^2 does not grow (<= 2x its value one
// iteration before; a linear rate multiplies it by 1/rate >= 5). The projected tangent alone (the
// behaviour before) converges linearly (8-13 solves per step here, 5 exact), and is run for comparison: the same
// equilibrium (1e-6), more Newton solves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mesh/structured_box.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/loads/region_conditions.hpp"
#include "solid/loads/surface_face.hpp"
#include "solid/tet/tet_model.hpp"

using namespace tetfsi;
using namespace tetfsi::solid;

namespace {

constexpr double kMu = 0.4225e6, kNu = 0.3, kThickness = 1e-3;

// The model with its projected tangent offered as the exact one: Newton on the projected tangent.
class ProjectedOnly : public ElasticModel {
 public:
  explicit ProjectedOnly(const TetModel& m) : m_(m) {}
  int num_nodes() const override { return m_.num_nodes(); }
  const Eigen::VectorXd& reference_positions() const override { return m_.reference_positions(); }
  const Eigen::VectorXd& lumped_masses() const override { return m_.lumped_masses(); }
  bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& f, SparseMatrix* K) const override {
    return m_.evaluate(d, f, K);
  }
  double strain_energy(const Eigen::VectorXd& d) const override { return m_.strain_energy(d); }

 private:
  const TetModel& m_;
};

struct Cook {
  mesh::TetMesh mesh;
  std::unique_ptr<TetModel> model;
  BoundaryConditions bc;
  int probe = -1;  // node at (48, 52, 0) mm

  Cook(int n, ConstitutiveLaw law) {
    mesh = mesh::structured_box({0, 0, 0}, {1, 1, kThickness}, n, n, 1);
    for (auto& v : mesh.vertices) {  // (s, t) in the unit square -> the trapezoid
      const double s = v.x(), t = v.y();
      const double y0 = 0.044 * s, y1 = 0.044 + 0.016 * s;
      v = {0.048 * s, y0 + t * (y1 - y0), v.z()};
    }
    probe = n + (n + 1) * (n / 2);
    TetMaterial m;
    m.youngs_modulus = 2 * kMu * (1 + kNu);
    m.poisson_ratio = kNu;
    m.law = law;
    TetModelOptions options;
    options.project_spd = true;  // as in the scenes' neo-Hookean tets
    model = std::make_unique<TetModel>(mesh, m, options);
    LoadedMesh loaded;
    loaded.vertices = mesh.vertices;
    loaded.boundary = tet_boundary_faces(mesh.tets);
    loaded.masses = model->lumped_masses();
    loaded.density = m.density;
    RegionCondition clamp, plane, load;
    clamp.lo = {-1, -1, -1};
    clamp.hi = {0, 1, 1};
    plane.components = "z";
    plane.lo = {-1, -1, -1};
    plane.hi = {1, 1, 1};
    load.kind = RegionCondition::Kind::Traction;
    load.lo = {0.048, -1, -1};
    load.hi = {1, 1, 1};
    load.value = {0, 1.0 / (0.016 * kThickness), 0};  // 1 N on the 16 mm x 1 mm end
    bc = make_conditions({clamp, plane, load}, loaded);
  }
};

}  // namespace

TEST(StaticNewton, CookMembraneTetsConvergeQuadratically) {
  for (ConstitutiveLaw law : {ConstitutiveLaw::kNeoHookeanStable, ConstitutiveLaw::kNeoHookeanBonetWood,
                              ConstitutiveLaw::kNeoHookeanSplit, ConstitutiveLaw::kStVK}) {
    const Cook cook(16, law);
    StaticOptions opt;
    opt.load_steps = 4;
    const StaticResult exact = solve_static(*cook.model, cook.bc, opt);
    const StaticResult projected = solve_static(ProjectedOnly(*cook.model), cook.bc, opt);
    const double uy = exact.displacement(3 * cook.probe + 1);
    std::printf("Cook %s, %d tets: u_y(48, 52) = %.5f mm (projected tangent: %.5f mm); Newton solves per "
                "load step, exact:", hyperelastic_law_name(law), cook.model->num_tets(), 1e3 * uy,
                1e3 * projected.displacement(3 * cook.probe + 1));
    for (const auto& s : exact.steps) std::printf(" %d", s.iterations);
    std::printf(", projected:");
    for (const auto& s : projected.steps) std::printf(" %d", s.iterations);
    std::printf("\n");
    EXPECT_NEAR(projected.displacement(3 * cook.probe + 1), uy, 1e-6 * uy);  // the same equilibrium
    int checked = 0;
    for (const auto& s : exact.steps) {
      const auto& r = s.residuals;
      std::printf("  lambda %.2f residuals:", s.load_factor);
      for (std::size_t k = 0; k < r.size(); ++k)
        std::printf(" %.2e%s", r[k], k ? ("(" + std::to_string(r[k] / r[k - 1]).substr(0, 6) + ")").c_str() : "");
      std::printf("; projected-tangent solves %d\n", s.modified_tangent_solves);
      std::size_t n = 0;  // first residual at the tolerance
      while (n < r.size() && r[n] > opt.residual_tolerance) ++n;
      ASSERT_LT(n, r.size());
      if (n < 2) continue;
      ++checked;
      for (std::size_t k : {n - 1, n})
        EXPECT_LE(r[k] / r[k - 1], 0.05) << hyperelastic_law_name(law) << " lambda " << s.load_factor << " k " << k;
      // Order of convergence p = log(r_n / r_{n-1}) / log(r_{n-1} / r_{n-2}): 1 for a linear rate,
      // 2 for Newton; and r_n / r_{n-1}^2 bounded (a linear rate would multiply it by r_{n-2}/r_{n-1}).
      const double order = std::log(r[n] / r[n - 1]) / std::log(r[n - 1] / r[n - 2]);
      const double q1 = r[n - 1] / (r[n - 2] * r[n - 2]), q2 = r[n] / (r[n - 1] * r[n - 1]);
      std::printf("    order %.2f, r_k / r_(k-1)^2 = %.3g then %.3g\n", order, q1, q2);
      if (r[n] > 1e-13) {  // above round-off (1e-15 .. 1e-13)
        EXPECT_GE(order, 1.8) << hyperelastic_law_name(law) << " lambda " << s.load_factor;
        EXPECT_LE(q2, 2 * q1) << hyperelastic_law_name(law) << " lambda " << s.load_factor;
      }
    }
    EXPECT_GE(checked, 2) << hyperelastic_law_name(law);
    EXPECT_LT(exact.total_iterations, projected.total_iterations) << hyperelastic_law_name(law);
  }
}

namespace {

// One node whose three components are springs f(u) = k u (1 - (u/a)^2)^2 (energy k a^2 / 6 (1 - (1 -
// (u/a)^2)^3)): exact tangent f'(u) = k (1 - (u/a)^2)(1 - 5 (u/a)^2), negative for a/sqrt(5) < |u| < a
// (a snap-through), and a modified tangent that leaves out the negative part, k (1 + 5 (u/a)^4) > 0.
class SnapSpring : public ElasticModel {
 public:
  int num_nodes() const override { return 1; }
  const Eigen::VectorXd& reference_positions() const override { return X_; }
  const Eigen::VectorXd& lumped_masses() const override { return m_; }
  bool modifies_tangent() const override { return true; }
  bool evaluate(const Eigen::VectorXd& d, Eigen::VectorXd& f, SparseMatrix* K) const override {
    return eval(d, f, K, false);
  }
  bool evaluate_exact(const Eigen::VectorXd& d, Eigen::VectorXd& f, SparseMatrix* K) const override {
    return eval(d, f, K, true);
  }
  double strain_energy(const Eigen::VectorXd& d) const override {
    double w = 0;
    for (int i = 0; i < 3; ++i) w += (1 - std::pow(1 - d(i) * d(i), 3)) / 6;
    return w;
  }

 private:
  bool eval(const Eigen::VectorXd& d, Eigen::VectorXd& f, SparseMatrix* K, bool exact) const {
    f.resize(3);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < 3; ++i) {
      const double u = d(i), s = 1 - u * u;
      f(i) = u * s * s;  // k = a = 1
      t.emplace_back(i, i, exact ? s * (1 - 5 * u * u) : 1 + 5 * u * u * u * u);
    }
    if (K) {
      K->resize(3, 3);
      K->setFromTriplets(t.begin(), t.end());
    }
    return true;
  }
  Eigen::VectorXd X_ = Eigen::VectorXd::Zero(3), m_ = Eigen::VectorXd::Ones(1);
};

}  // namespace

// Where the exact tangent is not positive definite (inside the snap-through) the solver takes the
// model's modified tangent for that solve, and returns to the exact one, with quadratic convergence,
// once past it: load f = 0.5 > max f(u < a) = 0.286 in one step from u = 0 must end at the root of
// u (1 - u^2)^2 = 0.5 above u = 1 (u = 1.27521 by bisection here), each component.
TEST(StaticNewton, FallsBackToTheModifiedTangentWhereTheExactOneIsIndefinite) {
  SnapSpring model;
  BoundaryConditions bc;
  bc.forces = Eigen::Vector3d(0.5, 0.5, 0.5);
  StaticOptions opt;
  opt.load_steps = 1;
  opt.max_iterations = 50;
  const StaticResult r = solve_static(model, bc, opt);
  double lo = 1.0, hi = 2.0;
  for (int k = 0; k < 100; ++k) {
    const double mid = 0.5 * (lo + hi);
    (mid * (1 - mid * mid) * (1 - mid * mid) < 0.5 ? lo : hi) = mid;
  }
  ASSERT_EQ(r.steps.size(), 1u);
  const auto& s = r.steps[0];
  std::printf("snap-through spring: u = %.10f (root %.10f), %d solves, %d with the modified tangent; residuals:",
              r.displacement(0), lo, s.iterations, s.modified_tangent_solves);
  for (double x : s.residuals) std::printf(" %.2e", x);
  std::printf("\n");
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.displacement(i), lo, 1e-9);
  EXPECT_GE(s.modified_tangent_solves, 1);
  EXPECT_LT(s.modified_tangent_solves, s.iterations);
  const auto& res = s.residuals;  // the last two ratios before the tolerance: quadratic
  std::size_t n = 0;
  while (n < res.size() && res[n] > opt.residual_tolerance) ++n;
  ASSERT_LT(n, res.size());
  ASSERT_GE(n, 2u);
  EXPECT_LE(res[n] / res[n - 1], 0.05);
  EXPECT_LE(res[n - 1] / res[n - 2], 0.05);
}
