// Loads of solid/loads/ on tet and hex8 solids through the static solver:
//  - follower pressure: its consistent load stiffness against central differences (triangles and
//    quads); a unit cube with symmetry planes x = y = z = 0 and pressure p on the other three faces
//    deforms homogeneously, x = lambda X, with Cauchy stress -p I exactly. For St. Venant-Kirchhoff,
//    sigma = S / lambda (F = lambda I), S = 3 K (lambda^2 - 1) / 2, K = lambda_L + 2 mu / 3, so
//      3 K lambda^2 + 2 p lambda - 3 K = 0,  lambda = (sqrt(p^2 + 9 K^2) - p) / (3 K),
//    which both meshes represent exactly (a homogeneous state); p = 0.1 E gives 3.9 % strain (the
//    small-strain Lame answer 1 - p / (3 K) is 2 % off in the displacement).
//  - body force: a bar [0, a]^2 x [0, L] hanging from z = L under b = -rho g e_z (N/m^3), nu = 0:
//    the end displacement is rho g L^2 / (2 E) (uniaxial stress, linear range).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "mesh/structured_box.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/block_mesh.hpp"
#include "solid/hex/hex_model.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/loads/follower_pressure.hpp"
#include "solid/loads/region_conditions.hpp"
#include "solid/tet/tet_model.hpp"

using namespace tetfsi;
using namespace tetfsi::solid;

namespace {

constexpr double kE = 1e6, kNu = 0.3, kRho = 1000;

struct Body {
  std::unique_ptr<ElasticModel> model;
  LoadedMesh loaded;
};

Body tet_body(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz, double nu,
              double E = kE) {
  const auto mesh = mesh::structured_box(lo, hi, nx, ny, nz);
  TetMaterial m;
  m.youngs_modulus = E;
  m.poisson_ratio = nu;
  m.density = kRho;
  Body b;
  auto model = std::make_unique<TetModel>(mesh, m);
  b.loaded = {mesh.vertices, tet_boundary_faces(mesh.tets), model->lumped_masses(), kRho};
  b.model = std::move(model);
  return b;
}

Body hex_body(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz, double nu,
              double E = kE) {
  auto mesh = hex::block_mesh(lo, hi, nx, ny, nz);
  hex::Material m;
  m.youngs_modulus = E;
  m.poisson_ratio = nu;
  m.density = kRho;
  Body b;
  b.loaded.vertices = mesh.vertices;
  for (const auto& q : hex::boundary_faces_in_box(mesh, lo, hi, 1e-9)) b.loaded.boundary.push_back(q);
  auto model = std::make_unique<hex::HexModel>(std::move(mesh), m);
  b.loaded.masses = model->lumped_masses();
  b.loaded.density = kRho;
  b.model = std::move(model);
  return b;
}

RegionCondition region(RegionCondition::Kind kind, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  RegionCondition c;
  c.kind = kind;
  c.lo = lo;
  c.hi = hi;
  return c;
}

// Central differences of the follower pressure force against its load stiffness.
double pressure_tangent_error(const PressureLoad& load, int num_nodes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-0.2, 0.2);
  Eigen::VectorXd X(3 * num_nodes), u(3 * num_nodes);
  const double square[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int i = 0; i < 3 * num_nodes; ++i) X(i) = square[i / 3][i % 3] + dist(rng), u(i) = dist(rng);
  SparseMatrix K(3 * num_nodes, 3 * num_nodes);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Ones(3 * num_nodes, 3 * num_nodes);
  K = dense.sparseView();
  K *= 0.0;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * num_nodes);
  add_follower_pressure({load}, X, u, 1.0, f, &K);
  const Eigen::MatrixXd Kd(K);
  double worst = 0;
  const double eps = 1e-6;
  for (int j = 0; j < 3 * num_nodes; ++j) {
    Eigen::VectorXd up = u, um = u, fp = Eigen::VectorXd::Zero(f.size()), fm = fp;
    up(j) += eps;
    um(j) -= eps;
    add_follower_pressure({load}, X, up, 1.0, fp, nullptr);
    add_follower_pressure({load}, X, um, 1.0, fm, nullptr);
    worst = std::max(worst, ((fp - fm) / (2 * eps) - Kd.col(j)).norm() / Kd.norm());
  }
  return worst;
}

// Solves the pressurised cube (file comment) and returns the worst |x - lambda X| / (lambda - 1).
double pressure_cube_error(const Body& b, double p, int* iterations) {
  using K = RegionCondition::Kind;
  std::vector<RegionCondition> c = {region(K::Fixed, {-1, -1, -1}, {0, 2, 2}), region(K::Fixed, {-1, -1, -1}, {2, 0, 2}),
                                    region(K::Fixed, {-1, -1, -1}, {2, 2, 0})};
  c[0].components = "x";
  c[1].components = "y";
  c[2].components = "z";
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d lo(-1, -1, -1), hi(2, 2, 2);
    lo(axis) = 1;
    auto face = region(K::Pressure, lo, hi);
    face.pressure = p;
    c.push_back(face);
  }
  const auto bc = make_conditions(c, b.loaded);
  StaticOptions opt;
  opt.load_steps = 2;
  const auto r = solve_static(*b.model, bc, opt);
  const double lame = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  const double bulk = lame + 2 * mu / 3;
  const double stretch = (std::sqrt(p * p + 9 * bulk * bulk) - p) / (3 * bulk);
  double worst = 0;
  for (std::size_t v = 0; v < b.loaded.vertices.size(); ++v)
    worst = std::max(worst, (r.displacement.segment<3>(3 * v) - (stretch - 1) * b.loaded.vertices[v]).norm());
  *iterations = 0;
  for (const auto& s : r.steps) *iterations = std::max(*iterations, s.iterations);
  std::printf("pressure cube: stretch exact %.8f (Lame small strain %.8f), worst node error %.3e of the "
              "displacement, <= %d Newton solves per step\n", stretch, 1 - p / (3 * bulk), worst / (1 - stretch),
              *iterations);
  return worst / (1 - stretch);
}

// Hanging bar (file comment): end displacement over rho g L^2 / (2 E), minus 1.
double hanging_bar_error(const Body& b, double L, double E) {
  using K = RegionCondition::Kind;
  const double g = 9.81;
  auto top = region(K::Fixed, {-1, -1, L}, {1, 1, 2 * L});
  auto weight = region(K::BodyForce, {-1, -1, -1}, {1, 1, 2 * L});
  weight.value = {0, 0, -kRho * g};
  const auto bc = make_conditions({top, weight}, b.loaded);
  const auto r = solve_static(*b.model, bc, StaticOptions{});
  const auto bottom = vertices_in_box(b.loaded.vertices, {-1, -1, -1}, {1, 1, 0}, 1e-9);
  double uz = 0;
  for (int v : bottom) uz += r.displacement(3 * v + 2) / bottom.size();
  const double exact = kRho * g * L * L / (2 * E);
  std::printf("hanging bar: end displacement %.6e m, rho g L^2 / (2E) = %.6e m, error %.3e\n", -uz, exact,
              -uz / exact - 1);
  return std::abs(-uz / exact - 1);
}

}  // namespace

TEST(FollowerPressure, LoadStiffnessMatchesFiniteDifferences) {
  PressureLoad tri{{{0, 1, 2, -1}}, 1.3e3}, quad{{{0, 1, 2, 3}}, -2.1e3};
  EXPECT_LT(pressure_tangent_error(tri, 3, 1), 1e-8);
  EXPECT_LT(pressure_tangent_error(quad, 4, 2), 1e-8);
}

// Exact homogeneous finite-strain state: 1e-8 of the displacement; Newton quadratic with the
// consistent (non-symmetric) tangent: at most 6 solves per load step (predictor included).
TEST(FollowerPressure, CubeUnderPressureMatchesExactStretchTet) {
  int its = 0;
  EXPECT_LT(pressure_cube_error(tet_body({0, 0, 0}, {1, 1, 1}, 3, 3, 3, kNu), 0.1 * kE, &its), 1e-8);
  EXPECT_LE(its, 6);
}

TEST(FollowerPressure, CubeUnderPressureMatchesExactStretchHex8) {
  int its = 0;
  EXPECT_LT(pressure_cube_error(hex_body({0, 0, 0}, {1, 1, 1}, 3, 3, 3, kNu), 0.1 * kE, &its), 1e-8);
  EXPECT_LE(its, 6);
}

// Hanging bar 0.1 x 0.1 x 1 m, nu = 0, E = 1e8 Pa (strain <= 1e-4, so the St. Venant-Kirchhoff
// nonlinearity, 1.5 x strain, stays at 1e-4; at E = 1e6 Pa it costs -1 %): end displacement within
// 1e-3 of rho g L^2 / (2E) on 2 x 2 x 20 cells (linear elements with consistent nodal loads are
// nodally exact for this 1D problem).
TEST(BodyForce, HangingBarEndDisplacementTet) {
  EXPECT_LT(hanging_bar_error(tet_body({0, 0, 0}, {0.1, 0.1, 1}, 2, 2, 20, 0.0, 1e8), 1.0, 1e8), 1e-3);
}

TEST(BodyForce, HangingBarEndDisplacementHex8) {
  EXPECT_LT(hanging_bar_error(hex_body({0, 0, 0}, {0.1, 0.1, 1}, 2, 2, 20, 0.0, 1e8), 1.0, 1e8), 1e-3);
}

// Dynamic run with a follower pressure (FollowerLoadedModel in the Newmark integrator, the path of
// the dynamic runners): the pressurised tet cube of CubeUnderPressureMatchesExactStretchTet at
// p = 0.02 E, Rayleigh alpha = 40 1/s, h = 0.01 s, 300 steps, settles at the exact static stretch
// (within 1e-6 of the displacement; the remaining motion decays like exp(-alpha t / 2)).
TEST(FollowerPressure, DampedDynamicCubeSettlesAtExactStretch) {
  const Body b = tet_body({0, 0, 0}, {1, 1, 1}, 2, 2, 2, kNu);
  std::vector<RegionCondition> faces;
  const double p = 0.02 * kE;
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d lo(-1, -1, -1), hi(2, 2, 2);
    lo(axis) = 1;
    auto face = region(RegionCondition::Kind::Pressure, lo, hi);
    face.pressure = p;
    faces.push_back(face);
  }
  const auto bc = make_conditions(faces, b.loaded);
  const FollowerLoadedModel loaded(*b.model, bc.pressures);
  NewmarkSettings settings;
  const double time_step = 0.01;
  settings.rayleigh_alpha = 40;
  NewmarkIntegrator integ(loaded, settings);
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d lo(-1, -1, -1), hi(2, 2, 2);
    hi(axis) = 0;
    std::array<bool, 3> held{false, false, false};
    held[axis] = true;
    integ.fix_components(vertices_in_box(b.loaded.vertices, lo, hi, 1e-9), held);
  }
  for (int k = 0; k < 300; ++k) integ.step(time_step);
  const double lame = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  const double bulk = lame + 2 * mu / 3;
  const double stretch = (std::sqrt(p * p + 9 * bulk * bulk) - p) / (3 * bulk);
  double worst = 0;
  for (std::size_t v = 0; v < b.loaded.vertices.size(); ++v)
    worst = std::max(worst, (integ.displacement().segment<3>(3 * v) - (stretch - 1) * b.loaded.vertices[v]).norm());
  std::printf("dynamic pressure cube: worst node error %.3e of the displacement after 3 s\n", worst / (1 - stretch));
  EXPECT_LT(worst / (1 - stretch), 1e-6);
}
