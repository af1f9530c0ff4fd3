// SurfaceContact (solid/contact/surface_contact.hpp) on a system whose answer is known: two free
// tets with lumped masses and no stiffness, A = M/h, b = (M/h) uⁿ, so that without contact
// u^{n+1} = uⁿ. The apex of a falling tet meets the top face of a heavier one below it: the active
// set must land the apex a film δ above the face at the end of the step, conserve the momentum of
// the pair, release a pair that would pull, and take Coulomb's bound μ f h off the sliding speed
// inside the same solve.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>

#include "solid/contact/closest_point.hpp"
#include "solid/contact/surface_contact.hpp"

namespace {

using tetfsi::solid::SurfaceContact;
using tetfsi::solid::SurfaceContactSettings;
using SparseMatrix = SurfaceContact::SparseMatrix;

struct TwoTets {
  // Floor tet: top face z = 0 (a large triangle), fourth node below; falling tet: apex down at z0.
  Eigen::VectorXd X{24}, masses{8};
  std::vector<std::array<int, 4>> tet{{0, 1, 2, 3}};
  explicit TwoTets(double apex_height) {
    X << -2, -2, 0, 2, -2, 0, 0, 2, 0, 0, 0, -1,                               // floor, nodes 0-3
        0, 0, apex_height, 0.5, 0, 1, -0.5, 0.5, 1, -0.5, -0.5, 1;             // faller, nodes 4-7
    masses << 2, 2, 2, 2, 1, 1, 1, 1;
  }
};

/// A, b of a free step: A = M/h per dof, b = (M/h) u.
void free_system(const Eigen::VectorXd& masses, double h, const Eigen::VectorXd& u, SparseMatrix& A, Eigen::VectorXd& b) {
  const int n = static_cast<int>(u.size());
  A.resize(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, masses[i / 3] / h);
  A.setFromTriplets(t.begin(), t.end());
  b = A * u;
}

Eigen::VectorXd solve(const SparseMatrix& A, const Eigen::VectorXd& b) {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(A);
  return ldlt.solve(b);
}

/// One step with the active set: as CoupledStepper::solve_with_contact does.
Eigen::VectorXd contact_step(SurfaceContact& contact, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                             const Eigen::VectorXd& masses, double h, int* rounds = nullptr) {
  SparseMatrix A_free, A;
  Eigen::VectorXd b_free, b;
  free_system(masses, h, u, A_free, b_free);
  contact.begin_step(h, x, u, std::vector<char>(u.size(), 0));
  A = A_free, b = b_free;
  if (contact.warm_start()) contact.add_rows(A, b);
  Eigen::VectorXd u_next = solve(A, b);
  int r = 1;
  for (; r < 9 && contact.update(u_next); ++r) {
    A = A_free, b = b_free;
    contact.add_rows(A, b);
    u_next = solve(A, b);
  }
  if (rounds) *rounds = r;
  contact.finish(u_next);
  return u_next;
}

Eigen::Vector3d momentum(const Eigen::VectorXd& masses, const Eigen::VectorXd& u) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int v = 0; v < masses.size(); ++v) p += masses[v] * u.segment<3>(3 * v);
  return p;
}

SurfaceContact make_contact(const TwoTets& s, double gap, double friction = 0) {
  SurfaceContactSettings settings;
  settings.gap = gap;
  settings.friction = friction;
  SurfaceContact contact(settings);
  contact.add_solid(s.tet, s.X.head(12), s.masses.head(4), 0);
  contact.add_solid(s.tet, s.X.tail(12), s.masses.tail(4), 12);
  return contact;
}

TEST(ClosestPoint, RegionsOfATriangle) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto cp = tetfsi::solid::closest_point_on_triangle({0.25, 0.25, 2}, a, b, c);  // face
  EXPECT_NEAR(cp.distance, 2, 1e-15);
  EXPECT_NEAR((cp.weight - Eigen::Vector3d(0.5, 0.25, 0.25)).norm(), 0, 1e-15);
  cp = tetfsi::solid::closest_point_on_triangle({0.5, -1, 0}, a, b, c);  // edge ab
  EXPECT_NEAR(cp.distance, 1, 1e-15);
  EXPECT_NEAR((cp.point - Eigen::Vector3d(0.5, 0, 0)).norm(), 0, 1e-15);
  cp = tetfsi::solid::closest_point_on_triangle({2, 2, 0}, a, b, c);  // edge bc
  EXPECT_NEAR((cp.point - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 0, 1e-15);
  cp = tetfsi::solid::closest_point_on_triangle({-1, -1, 1}, a, b, c);  // vertex a
  EXPECT_NEAR(cp.weight[0], 1, 0);
  EXPECT_NEAR(cp.distance, std::sqrt(3.0), 1e-15);
}

TEST(SurfaceContact, FallingApexLandsAFilmAboveTheFaceAndConservesMomentum) {
  const double h = 0.1, gap = 0.01, apex = 0.05, speed = 1.0;
  TwoTets s(apex);
  SurfaceContact contact = make_contact(s, gap);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(24);
  for (int v = 4; v < 8; ++v) u[3 * v + 2] = -speed;
  int rounds = 0;
  const Eigen::VectorXd u_next = contact_step(contact, s.X, u, s.masses, h, &rounds);
  ASSERT_GE(contact.num_active(), 1);
  EXPECT_GE(rounds, 2);
  // End-of-step positions (Chentanez et al. 2006, eq. 5): the apex is δ above the face's plane, which moved down.
  const Eigen::VectorXd x_next = s.X + 0.5 * h * (u + u_next);
  // The apex is over the face's point y = (x0 + x1)/4 + x2/2 (barycentric weights at (0, 0)).
  const double face_z = 0.25 * x_next[3 * 0 + 2] + 0.25 * x_next[3 * 1 + 2] + 0.5 * x_next[3 * 2 + 2];
  // The penalty holds the constraint to about 1/κ of the step's closing distance h × speed.
  const double kappa = SurfaceContactSettings{}.penalty;
  EXPECT_NEAR(x_next[3 * 4 + 2] - face_z, gap, 2.0 / kappa * h * speed);
  EXPECT_LT(face_z, 0.0);  // the floor tet was pushed
  const Eigen::Vector3d p0 = momentum(s.masses, u), p1 = momentum(s.masses, u_next);
  // To the round-off of a penalty solve: κ ε ≈ 1e7 × 2.2e-16 relative.
  EXPECT_LT((p1 - p0).norm(), 1e-8 * p0.norm()) << "momentum before " << p0.transpose() << ", after " << p1.transpose();
  // Only the apex is constrained (the other nodes stay far from the floor).
  EXPECT_EQ(contact.num_active(), 1);
  for (int v = 5; v < 8; ++v) EXPECT_NEAR(u_next[3 * v + 2], -speed, 1e-12);
}

TEST(SurfaceContact, SeparatingPairIsReleased) {
  // The apex rests touching the film (gap δ) and moves away: the warm-started pair would pull.
  const double h = 0.1, gap = 0.01;
  TwoTets s(gap);
  SurfaceContact contact = make_contact(s, gap);
  contact.set_touching_nodes({4}, {0.0});
  Eigen::VectorXd u = Eigen::VectorXd::Zero(24);
  for (int v = 4; v < 8; ++v) u[3 * v + 2] = 0.5;
  const Eigen::VectorXd u_next = contact_step(contact, s.X, u, s.masses, h);
  EXPECT_EQ(contact.num_active(), 0);
  EXPECT_NEAR((u_next - u).norm(), 0, 1e-12);
}

TEST(SurfaceContact, CoulombFrictionTakesMuFhOffTheSlidingSpeed) {
  const double h = 0.1, gap = 0.01, apex = 0.02, mu = 0.1;
  TwoTets s(apex);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(24);
  for (int v = 4; v < 8; ++v) u[3 * v] = 2.0, u[3 * v + 2] = -1.0;  // sliding along x while falling
  SurfaceContact frictionless = make_contact(s, gap);
  const Eigen::VectorXd u_slide = contact_step(frictionless, s.X, u, s.masses, h);
  SurfaceContact rough = make_contact(s, gap, mu);
  const Eigen::VectorXd u_next = contact_step(rough, s.X, u, s.masses, h);
  ASSERT_EQ(rough.num_active(), 1);
  // Normal force from the frictionless solve's change of the apex's momentum, f h = m Δu_z.
  const double impulse_normal = s.masses[4] * (u_slide[3 * 4 + 2] - u[3 * 4 + 2]);
  ASSERT_GT(impulse_normal, 0);
  // Friction slows the sliding (P = μ f h, not enough to stop it here) and keeps the momentum.
  const double slide_before = u_slide[3 * 4] - u_slide[0];
  const double slide_after = u_next[3 * 4] - u_next[0];
  EXPECT_LT(slide_after, slide_before);
  EXPECT_GT(slide_after, 0);
  const Eigen::Vector3d p0 = momentum(s.masses, u), p1 = momentum(s.masses, u_next);
  EXPECT_LT((p1 - p0).norm(), 1e-8 * p0.norm());
  // The apex's own loss of tangential momentum is the friction impulse μ f h, to the 1% to which
  // the rounds converge the lagged friction coefficient (surface_contact.hpp).
  EXPECT_NEAR(s.masses[4] * (u_slide[3 * 4] - u_next[3 * 4]), mu * impulse_normal, 0.02 * mu * impulse_normal);
}

}  // namespace
