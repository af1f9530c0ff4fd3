// Validation: cantilever under an end moment (Euler-Bernoulli elastica: uniform curvature M / (EI)).
// Exact elastica: uniform curvature M/EI, end rotation theta = M L / EI, tip (end-face centroid)
//   x = (EI/M) sin(ML/EI) = L sin(theta)/theta,  y = (EI/M)(1 - cos(ML/EI)) = L (1 - cos theta)/theta
// relative to the root centroid; at M = 2 pi EI / L the beam closes into a full circle.
// The moment is applied as a prescribed rotation theta of the end face with free translation
// (RotatingFace: a pure couple that turns with the section); M is the measured reaction.
#include <gtest/gtest.h>

#include <cmath>

#include "solid/hex/block_mesh.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/hex_model.hpp"

using namespace tetfsi::solid;
using namespace tetfsi::solid::hex;

namespace {

struct Cantilever {
  double L = 1.0, h = 0.05, b = 0.05;  // L/h = 20
  Material material;
  tetfsi::mesh::HexMesh mesh;
  std::vector<int> end_nodes;
  BoundaryConditions bc;
  double EI() const { return material.youngs_modulus * b * h * h * h / 12.0; }

  Cantilever(int nx, int ny, int nz, double theta) {
    material.law = MaterialLaw::kStVK;
    material.youngs_modulus = 1.0e7;
    material.poisson_ratio = 0.0;  // Euler-Bernoulli comparison without anticlastic curvature
    mesh = block_mesh({0, 0, 0}, {L, h, b}, nx, ny, nz);
    fix_nodes(bc, nodes_in_box(mesh, {0, 0, 0}, {0, h, b}));
    end_nodes = nodes_in_box(mesh, {L, 0, 0}, {L, h, b});
    RotatingFace face;
    face.nodes = end_nodes;
    face.center = {L, h / 2, b / 2};
    face.axis = Eigen::Vector3d::UnitZ();
    face.angle = theta;
    bc.rotating_faces.push_back(face);
  }
  Eigen::Vector3d tip(const Eigen::VectorXd& u) const {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : end_nodes) c += mesh.vertices[v] + u.segment<3>(3 * v);
    return c / static_cast<double>(end_nodes.size());
  }
  Eigen::Vector3d exact_tip(double theta) const {
    return {L * std::sin(theta) / theta, h / 2 + L * (1 - std::cos(theta)) / theta, b / 2};
  }
};

}  // namespace

// Roll-up to a full circle in 16 rotation steps on 100 x 2 x 1 hexes (element length / h = 0.2).
// Checked at every step: tip position against the exact elastica within 1 % of L, and the reaction
// moment against EI theta / L within 4 %. Expected moment errors: shear locking of fully integrated
// trilinear hexes makes the beam stiffer by ~ (G/E)(dx/h)^2 = 2 % (seen at small theta: +2.0 %);
// the St. Venant-Kirchhoff law softens in compression, and the fibre strains reach pi h / L = 16 %
// at theta = 2 pi, which bends the moment-curvature curve down (-2.5 % at 2 pi here, -4.2 % on the
// finer, less locked 200 x 4 x 2 mesh of bench_hex). The tip position does not depend on the
// moment law as long as the curvature is uniform, so it is the sharp check. At theta = 2 pi the
// tip is back at the root within 2 % of L (the benchmark, at a finer resolution, checks 1 %).
// The error budget above is the standard element's: the enhanced one (hex8_enhanced.hpp) does not
// lock, and its moment at 2 pi is the softening alone (-4.5% on this mesh), outside the 4% band.
TEST(HexCantilever, EndMomentRollsUpIntoCircle) {
  const double theta_max = 2 * M_PI;
  Cantilever c(100, 2, 1, theta_max);
  const HexModel model(c.mesh, c.material, Hex8Formulation::Standard);
  StaticOptions opt;
  opt.load_steps = 16;
  opt.log = false;
  double worst_tip = 0.0, worst_moment = 0.0;
  int steps = 0;
  solve_static(model, c.bc, opt, 1.0, [&](const StepLog& s, const Eigen::VectorXd& u) {
    const double theta = s.load_factor * theta_max;
    const double tip_err = (c.tip(u) - c.exact_tip(theta)).norm() / c.L;
    Eigen::Vector3d F, M;
    face_reaction(model, c.bc.rotating_faces[0], u, F, M);
    const double M_exact = c.EI() * theta / c.L;
    const double m_err = std::abs(M.z() - M_exact) / M_exact;
    std::printf("theta %.4f: iterations %d, tip error %.3e L, moment %.5g (exact %.5g, rel err %.3e), |net force| %.2e\n",
                theta, s.iterations, tip_err, M.z(), M_exact, m_err, F.norm());
    EXPECT_LT(tip_err, 0.01) << "theta " << theta;
    EXPECT_LT(m_err, 0.04) << "theta " << theta;
    EXPECT_LT(F.norm(), 1e-6 * M_exact / c.h);
    worst_tip = std::max(worst_tip, tip_err);
    worst_moment = std::max(worst_moment, m_err);
    ++steps;
    if (s.load_factor == 1.0) {
      const Eigen::Vector3d root(0, c.h / 2, c.b / 2);
      const double gap = (c.tip(u) - root).norm() / c.L;
      std::printf("full circle: tip-root gap %.3e L\n", gap);
      EXPECT_LT(gap, 0.02);
    }
  });
  EXPECT_EQ(steps, 16);
  std::printf("worst tip error %.3e L, worst moment error %.3e\n", worst_tip, worst_moment);
}

// Small end moment as a dead linear traction (add_end_moment_traction): the tip follows the
// elastica for theta = M L / EI = 0.2 (where the dead load differs from a follower moment by
// O(theta^2) ~ 1 % in the moment's direction); tolerance 5 % of the tip deflection (locking ~ 2 %).
TEST(HexCantilever, DeadMomentTractionSmallRotation) {
  Cantilever c(100, 2, 1, 0.0);
  c.bc.rotating_faces.clear();
  const double theta = 0.2;
  const double M = c.EI() * theta / c.L;
  const auto faces = boundary_faces_in_box(c.mesh, {c.L, 0, 0}, {c.L, c.h, c.b});
  ASSERT_EQ(faces.size(), 2u);
  add_end_moment_traction(c.bc, c.mesh.vertices, faces, Eigen::Vector3d::UnitZ(), M);
  const HexModel model(c.mesh, c.material);
  StaticOptions opt;
  opt.load_steps = 2;
  const auto r = solve_static(model, c.bc, opt);
  const Eigen::Vector3d tip = c.tip(r.displacement), exact = c.exact_tip(theta);
  const double deflection = exact.y() - c.h / 2;
  std::printf("dead moment: tip y %.6f exact %.6f (rel %.3e)\n", tip.y() - c.h / 2, deflection,
              (tip.y() - exact.y()) / deflection);
  EXPECT_NEAR(tip.y(), exact.y(), 0.05 * deflection);
}
