// Static Newton solver (solid/analysis/static_solver.hpp, on hex8 models): quadratic convergence, the patch test
// through the solver, bad input and non-convergence errors, determinism, VTU output.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../test_support.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "solid/hex/block_mesh.hpp"
#include "solid/hex/block_problem.hpp"
#include "solid/hex/hex_output.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/hex_model.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::hex;

namespace {

Material neo_hookean() {
  Material m;
  m.law = MaterialLaw::kNeoHookeanBonetWood;
  m.youngs_modulus = 1.0e6;
  m.poisson_ratio = 0.3;
  return m;
}

// A unit cube of 4^3 hexes, bottom on rollers (z = 0), top pushed down by `dz` (prescribed z
// only), sides free, two bottom nodes pinned against rigid motion: homogeneous uniaxial compression.
struct Compression {
  tetfsi::mesh::HexMesh mesh = block_mesh({0, 0, 0}, {1, 1, 1}, 4, 4, 4);
  BoundaryConditions bc;
  /// bonded: the top is also held in x and y (platens that grip): inhomogeneous barrelling.
  explicit Compression(double dz, bool bonded = false) {
    const auto bottom = nodes_in_box(mesh, {-1, -1, 0}, {2, 2, 0});
    const auto top = nodes_in_box(mesh, {-1, -1, 1}, {2, 2, 1});
    fix_component(bc, bottom, 2);
    for (int v : top) bc.prescribed.emplace_back(3 * v + 2, dz);
    if (bonded) {
      fix_component(bc, top, 0);
      fix_component(bc, top, 1);
    }
    fix_component(bc, {0}, 0);  // node (0,0,0): no rigid x/y translation
    fix_component(bc, {0}, 1);
    fix_component(bc, {4}, 1);  // node (4,0,0): no rigid rotation about z
  }
};

}  // namespace

// Newton on a 30 % compression of a neo-Hookean block between gripping platens (inhomogeneous, so
// K_NL matters): every load step converges and the last
// iterations show quadratic decrease, r_{k+1} <= C r_k^2 (C = 10) once r_k < 1e-2 and above the
// round-off floor (1e-12). Residual ratios are printed.
TEST(HexStatic, NewtonConvergesQuadratically) {
  Compression c(-0.3, true);
  const HexModel model(c.mesh, neo_hookean());
  StaticOptions opt;
  opt.load_steps = 3;
  opt.residual_tolerance = 1e-11;
  const StaticResult r = solve_static(model, c.bc, opt);
  ASSERT_EQ(r.steps.size(), 3u);
  int quadratic_pairs = 0;
  for (const auto& s : r.steps) {
    std::printf("lambda %.3f:", s.load_factor);
    for (std::size_t k = 0; k < s.residuals.size(); ++k) {
      std::printf(" r=%.2e", s.residuals[k]);
      if (k > 0) std::printf(" (r/r_prev^2=%.2e)", s.residuals[k] / std::pow(s.residuals[k - 1], 2));
    }
    std::printf("\n");
    for (std::size_t k = 0; k + 1 < s.residuals.size(); ++k) {
      if (s.residuals[k] < 1e-2 && s.residuals[k + 1] > 1e-12) {
        EXPECT_LE(s.residuals[k + 1], 10.0 * s.residuals[k] * s.residuals[k]) << "step " << s.load_factor << " k " << k;
        ++quadratic_pairs;
      }
    }
    EXPECT_LE(s.iterations, 8);
  }
  EXPECT_GE(quadratic_pairs, 3);
  // The top was moved by exactly -0.3.
  EXPECT_NEAR(r.displacement(3 * (c.mesh.num_vertices() - 1) + 2), -0.3, 1e-14);
}

// Patch test through the solver: prescribe u = A X + b on the boundary of a distorted block and
// solve (finite strain, several Newton iterations) for the interior: the linear field is recovered.
TEST(HexStatic, PatchTestRecoversLinearFieldInInterior) {
  auto mesh = block_mesh({0, 0, 0}, {1, 1, 1}, 3, 3, 3);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> jitter(-0.08, 0.08);
  const auto boundary_faces = boundary_faces_in_box(mesh, {-1, -1, -1}, {2, 2, 2});
  std::vector<char> on_boundary(mesh.num_vertices(), 0);
  for (const auto& q : boundary_faces) for (int v : q) on_boundary[v] = 1;
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    if (!on_boundary[i]) mesh.vertices[i] += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
  }
  Material m;
  m.law = MaterialLaw::kStVK;
  m.youngs_modulus = 1e6;
  m.poisson_ratio = 0.25;
  const HexModel model(mesh, m);
  Eigen::Matrix3d A;
  A << 0.1, -0.05, 0.02, 0.03, -0.08, 0.04, -0.02, 0.05, 0.12;
  const Eigen::Vector3d b(0.01, 0.02, -0.03);
  BoundaryConditions bc;
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    if (!on_boundary[i]) continue;
    const Eigen::Vector3d u = A * mesh.vertices[i] + b;
    for (int k = 0; k < 3; ++k) bc.prescribed.emplace_back(3 * i + k, u(k));
  }
  StaticOptions opt;
  opt.load_steps = 2;
  opt.residual_tolerance = 1e-13;
  opt.increment_tolerance = 1e-13;
  const StaticResult r = solve_static(model, bc, opt);
  double err = 0.0;
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    err = std::max(err, (r.displacement.segment<3>(3 * i) - (A * mesh.vertices[i] + b)).norm());
  }
  EXPECT_LT(err, 1e-10);
}

// Same input and thread count -> same output; here also the same output for any thread count
// (coloured assembly): two solves must agree bit for bit.
TEST(HexStatic, Deterministic) {
  Compression c(-0.1);
  const HexModel model(c.mesh, neo_hookean());
  StaticOptions opt;
  opt.load_steps = 1;
  const auto r1 = solve_static(model, c.bc, opt);
  const auto r2 = solve_static(model, c.bc, opt);
  EXPECT_EQ((r1.displacement - r2.displacement).cwiseAbs().maxCoeff(), 0.0);
}

// Inconsistent input is refused with a message naming the cause.
TEST(HexStatic, BadInputIsReported) {
  Compression c(-0.1);
  const HexModel model(c.mesh, neo_hookean());
  BoundaryConditions twice = c.bc;
  twice.fixed_dofs.push_back(twice.fixed_dofs.front());
  EXPECT_THROW(solve_static(model, twice), std::invalid_argument);
  BoundaryConditions wrong_forces = c.bc;
  wrong_forces.forces = Eigen::VectorXd::Zero(5);
  EXPECT_THROW(solve_static(model, wrong_forces), std::invalid_argument);
  auto bad = c.mesh;
  std::swap(bad.hexes[0][0], bad.hexes[0][4]);  // inverted node order
  EXPECT_THROW(HexModel(bad, neo_hookean()), std::invalid_argument);
  Material m = neo_hookean();
  m.poisson_ratio = 0.5;
  EXPECT_THROW(HexModel(c.mesh, m), std::invalid_argument);
}

// An impossible load (crushing the block to below zero height) must end in NonConvergence with a
// message, not in NaNs or a crash.
TEST(HexStatic, CrushingReportsNonConvergence) {
  Compression c(-1.2);
  const HexModel model(c.mesh, neo_hookean());
  StaticOptions opt;
  opt.load_steps = 1;
  opt.max_step_cuts = 2;
  try {
    solve_static(model, c.bc, opt);
    FAIL() << "expected NonConvergence";
  } catch (const NonConvergence& e) {
    EXPECT_NE(std::string(e.what()).find("did not converge"), std::string::npos) << e.what();
    std::printf("message: %s\n", e.what());
  }
}

// Output: the written .vtu reads back (VTK's reader and ours) with the displacement and stress fields.
TEST(HexStatic, WritesDisplacementAndStress) {
  Compression c(-0.1);
  const HexModel model(c.mesh, neo_hookean());
  const auto r = solve_static(model, c.bc);
  tetfsi::test::TempDir dir("hex_out");
  const auto file = dir.path() / "block.vtu";
  write_hex_vtu(file, model, r.displacement);
  int status = -1;
  const std::string described = tetfsi::test::vtk_describe(file, &status);  // VTK's own reader
  EXPECT_EQ(status, 0);
  EXPECT_NE(described.find("125 64 p:displacement:3 c:cauchy_stress:6"), std::string::npos) << described;
  const auto grid = tetfsi::mesh::io::read_vtu(file);
  ASSERT_EQ(grid.num_cells(), 64);
  ASSERT_EQ(grid.point_data.size(), 1u);
  EXPECT_EQ(grid.point_data[0].name, "displacement");
  ASSERT_EQ(grid.cell_data.size(), 3u);
  // Uniaxial compression with free sides: sigma_zz ~ uniform, the others ~ 0.
  const auto& sigma = grid.cell_data[0].values;
  for (int e = 0; e < 64; ++e) {
    EXPECT_LT(sigma[6 * e + 2], 0.0);
    EXPECT_LT(std::abs(sigma[6 * e + 0]), 1e-6 * std::abs(sigma[6 * e + 2]));
  }
  Eigen::VectorXd nan = r.displacement;
  nan(0) = std::nan("");
  EXPECT_THROW(write_hex_vtu(dir.path() / "nan.vtu", model, nan), std::runtime_error);
}

// A scene-style problem (block_problem.hpp): a neo-Hookean cube on rollers under a dead uniform
// pressure traction t on its top. Exact: homogeneous uniaxial state with first Piola-Kirchhoff
// stress P_zz = F_zz S_zz = t (traction per reference area), P_xx = P_yy = 0, in every element.
TEST(HexStatic, BlockProblemUnderDeadTraction) {
  BlockProblem p;
  p.lo = {0, 0, 0};
  p.hi = {1, 1, 1};
  p.nx = p.ny = p.nz = 3;
  p.material = neo_hookean();
  const double t = -2.0e5;  // 20 % of E: large strain
  using K = RegionCondition::Kind;
  RegionCondition bottom{K::Fixed, {-1, -1, 0}, {2, 2, 0}, "z"};
  RegionCondition pin{K::Fixed, {0, 0, 0}, {0, 0, 0}, "xy"};
  RegionCondition pin2{K::Fixed, {1, 0, 0}, {1, 0, 0}, "y"};
  RegionCondition top{K::Traction, {-1, -1, 1}, {2, 2, 1}};
  top.value = {0, 0, t};
  p.conditions = {bottom, pin, pin2, top};
  p.options.load_steps = 4;
  const auto model = make_model(p);
  const auto bc = make_conditions(p, *model);
  const auto r = solve_static(*model, bc, p.options);
  std::vector<double> cauchy, pk2;
  model->element_stresses(r.displacement, cauchy, pk2);
  const double Fzz = 1.0 + r.displacement(3 * (model->num_nodes() - 1) + 2);  // top corner z / 1
  for (int e = 0; e < model->mesh().num_hexes(); ++e) {
    EXPECT_NEAR(Fzz * pk2[6 * e + 2], t, 1e-7 * std::abs(t));
    EXPECT_NEAR(pk2[6 * e + 0], 0.0, 1e-7 * std::abs(t));
  }
  RegionCondition nowhere{K::Fixed, {5, 5, 5}, {6, 6, 6}};
  p.conditions.push_back(nowhere);
  EXPECT_THROW(make_conditions(p, *model), std::invalid_argument);
}
