// The closed fluid regions of coupling/closed_regions.hpp on a ball in a closed box of water
// (CGAL complex, fluid subdomain 1, ball subdomain 2):
//  - the region's volume is the sum of its fluid tets' volumes (the box less the meshed ball), and
//    its gradient a = ∂V/∂x gives the exact rates of the divergence theorem: aᵀu = 0 for rigid
//    motions of the ball and aᵀu = −3εV_ball for its uniform dilatation u = εx (the fluid loses
//    what the ball gains);
//  - the start-velocity projection leaves aᵀu = 0, changes nothing that already keeps the volume,
//    and removes the kinetic energy (aᵀu)²/(2 aᵀM⁻¹a) of the M-orthogonal projection;
//  - a heavy soft ball dropped onto the floor of the closed box keeps its volume within 1e-4 (its
//    volume can change only by what the fluid, which cannot, gives up), where eq. (7) of
//    Chentanez et al. 2006 alone loses more than ten times that in the same run.
#include <gtest/gtest.h>

#include <cmath>

#include "coupling/closed_regions.hpp"
#include "coupling/coupled_stepper.hpp"
#include "fluid/boundary/boundary_conditions.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"

using namespace tetfsi;

namespace {

mesh::TetMesh ball_in_box(double edge_near) {
  mesh::MeshSizing sizing;
  sizing.edge_length = 0.15;
  sizing.edge_length_near_solids = edge_near;
  sizing.grading_distance = 0.25;
  sizing.facet_distance = 0.1 * edge_near;
  return mesh::build_complex({-0.4, -0.4, -0.4}, {0.4, 0.4, 0.4}, {mesh::make_sphere(0.1, 3)}, sizing);
}

struct Region {
  fluid::FluidMesh fm;
  std::vector<int> unknown, solid_node;
  fluid::ClassifiedBoundary bc;
  int num_solid_nodes = 0;
  double fluid_volume = 0, ball_volume = 0;
};

Region closed_ball_region(const mesh::TetMesh& m) {
  Region r;
  r.fm = fluid::build_fluid_mesh(m);
  r.unknown.resize(r.fm.num_nodes());
  for (int i = 0; i < r.fm.num_nodes(); ++i) r.unknown[i] = i;  // walls only: every node an unknown
  r.bc.flux = Eigen::VectorXd::Zero(r.fm.num_nodes());
  r.solid_node.assign(m.num_vertices(), -1);
  for (int t = 0; t < m.num_tets(); ++t) {
    const auto& v = m.tets[t];
    const double vol = mesh::signed_volume(m.vertices[v[0]], m.vertices[v[1]], m.vertices[v[2]], m.vertices[v[3]]);
    if (m.subdomain[t] == mesh::kFluidSubdomain) {
      r.fluid_volume += vol;
      continue;
    }
    r.ball_volume += vol;
    for (int a : v)
      if (r.solid_node[a] < 0) r.solid_node[a] = r.num_solid_nodes++;
  }
  return r;
}

}  // namespace

TEST(ClosedRegions, VolumeAndItsRatesFollowTheDivergenceTheorem) {
  const mesh::TetMesh m = ball_in_box(0.06);
  const Region r = closed_ball_region(m);
  const auto regions = coupling::find_closed_regions(r.fm, r.unknown, r.bc, r.solid_node);
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_NEAR(coupling::region_volume(regions[0], m.vertices), r.fluid_volume, 1e-12 * r.fluid_volume);
  EXPECT_NEAR(r.fluid_volume + r.ball_volume, 0.8 * 0.8 * 0.8, 1e-12);
  const Eigen::VectorXd a =
      coupling::region_volume_gradient(regions[0], m.vertices, r.solid_node, 3 * r.num_solid_nodes);
  Eigen::VectorXd translate(a.size()), rotate(a.size()), dilate(a.size());
  const Eigen::Vector3d omega(0.3, -1.1, 0.7), velocity(0.2, -0.5, 1.3);
  const double epsilon = 0.01;
  for (int v = 0; v < m.num_vertices(); ++v) {
    const int s = r.solid_node[v];
    if (s < 0) continue;
    translate.segment<3>(3 * s) = velocity;
    rotate.segment<3>(3 * s) = omega.cross(m.vertices[v]);
    dilate.segment<3>(3 * s) = epsilon * m.vertices[v];
  }
  const double scale = a.cwiseAbs().sum();
  EXPECT_NEAR(a.dot(translate), 0.0, 1e-13 * scale);
  EXPECT_NEAR(a.dot(rotate), 0.0, 1e-13 * scale);
  EXPECT_NEAR(a.dot(dilate), -3 * epsilon * r.ball_volume, 1e-12 * r.ball_volume);
  // A region with an open node is not closed.
  std::vector<int> open = r.unknown;
  open[0] = -1;
  EXPECT_TRUE(coupling::find_closed_regions(r.fm, open, r.bc, r.solid_node).empty());
}

TEST(ClosedRegions, StartVelocityProjectionKeepsTheVolumeAndOnlyRemovesEnergy) {
  const mesh::TetMesh m = ball_in_box(0.06);
  const Region r = closed_ball_region(m);
  const int n = 3 * r.num_solid_nodes;
  coupling::ClosedVolumes volumes;
  ASSERT_EQ(volumes.begin_step(r.fm, r.unknown, r.bc, r.solid_node, std::vector<char>(n, 0), m.vertices), 1);
  const Eigen::VectorXd& a = volumes.gradient(0);
  Eigen::VectorXd masses = Eigen::VectorXd::LinSpaced(r.num_solid_nodes, 0.5, 2.0);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) u[i] = std::sin(1.7 * i) + 0.1 * (i % 3);
  double flux = a.dot(u), inverse_mass_norm = 0;
  for (int i = 0; i < n; ++i) inverse_mass_norm += a[i] * a[i] / masses[i / 3];
  ASSERT_GT(std::abs(flux), 1e-6);
  coupling::ClosedVolumeReport report;
  const Eigen::VectorXd before = u;
  volumes.project_start_velocity(u, masses, std::vector<char>(n, 0), report);
  EXPECT_NEAR(a.dot(u), 0.0, 1e-12 * std::abs(flux));
  EXPECT_NEAR(report.removed_kinetic, 0.5 * flux * flux / inverse_mass_norm, 1e-10 * report.removed_kinetic);
  double kinetic_before = 0, kinetic_after = 0;
  for (int i = 0; i < n; ++i) {
    kinetic_before += 0.5 * masses[i / 3] * before[i] * before[i];
    kinetic_after += 0.5 * masses[i / 3] * u[i] * u[i];
  }
  EXPECT_NEAR(kinetic_before - kinetic_after, report.removed_kinetic, 1e-10 * kinetic_before);
  // Projecting again changes nothing.
  const Eigen::VectorXd once = u;
  volumes.project_start_velocity(u, masses, std::vector<char>(n, 0), report);
  EXPECT_LT((u - once).norm(), 1e-12 * once.norm());
}

namespace {

/// Largest |V_ball/V_ball,0 − 1| over a heavy soft ball's drop onto the floor of the closed box.
double ball_volume_drift(bool keep_closed_volumes) {
  fluid::FluidParams fp;
  fp.density = 1000;
  fp.gravity = Eigen::Vector3d(0, -9.81, 0);
  solid::TetMaterial mat;
  mat.density = 4000;
  mat.youngs_modulus = 1e5;
  mat.poisson_ratio = 0.3;
  mat.law = solid::ConstitutiveLaw::kNeoHookeanStable;
  coupling::CoupledSettings cs;
  cs.solid_gravity = fp.gravity;
  cs.keep_closed_volumes = keep_closed_volumes;
  cs.max_step_halvings = 6;
  coupling::CoupledStepper stepper(ball_in_box(0.06), fp, {mat}, cs);
  solid::StaticObstacles& walls = stepper.solid(0).obstacles();
  walls.add_plane({Eigen::Vector3d(0, -0.4 + 0.03, 0), Eigen::Vector3d(0, 1, 0)});  // the floor, a 3 cm film
  const solid::TetModel& model = stepper.solid_model(0);
  const auto volume = [&] {
    const Eigen::VectorXd x = stepper.solid(0).positions();
    double v = 0;
    for (const auto& t : model.tets())
      v += mesh::signed_volume(x.segment<3>(3 * t[0]), x.segment<3>(3 * t[1]), x.segment<3>(3 * t[2]),
                               x.segment<3>(3 * t[3]));
    return v;
  };
  const double v0 = volume();
  double drift = 0;
  for (int s = 0; s < 24; ++s) {  // lands at about 0.33 s, 0.8 s in all
    stepper.step(1.0 / 30);
    drift = std::max(drift, std::abs(volume() / v0 - 1));
  }
  return drift;
}

}  // namespace

TEST(ClosedRegions, HeavySoftBallLandingInAClosedTankKeepsItsVolume) {
  const double kept = ball_volume_drift(true);
  const double plain = ball_volume_drift(false);
  std::printf("ball volume drift: %.2e kept, %.2e with eq. (7) alone\n", kept, plain);
  EXPECT_LT(kept, 1e-4);
  EXPECT_GT(plain, 10 * kept);
}
