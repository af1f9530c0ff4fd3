// Validation of the Belytschko-Tsay membrane (solid/membrane/): patch test, hourglass/rigid modes,
// and the equilibrium of a pressurised cylinder (N / R = p, Laplace's law for a cylinder).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

#include "solid/membrane/membrane.hpp"
#include "solid/membrane/membrane_mesh.hpp"

using namespace tetfsi::membrane;

namespace {
constexpr double kPi = 3.14159265358979323846;

MembraneMaterial material() {
  MembraneMaterial m;
  m.rho = 1000;
  m.youngs = 1e6;
  m.poisson = 0.3;
  m.thickness = 0.01;
  return m;
}

/// A 3 x 3 patch of the unit square with distorted interior nodes, rotated into a tilted plane.
QuadMesh distorted_patch(const Mat3& R) {
  QuadMesh m = rectangle_mesh(Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), 3, 3);
  const double dx[4][2] = {{0.07, -0.05}, {-0.06, 0.04}, {0.05, 0.08}, {-0.04, -0.07}};
  const int interior[4] = {5, 6, 9, 10};
  for (int i = 0; i < 4; ++i) m.nodes[interior[i]] += Vec3(dx[i][0], dx[i][1], 0);
  for (auto& x : m.nodes) x = R * x;
  return m;
}
}  // namespace

TEST(Membrane, DistortedPatchUniformStretchGivesUniformStress) {
  const Mat3 R = (Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  const QuadMesh mesh = distorted_patch(R);
  Membrane mem(mesh.nodes, mesh.quads, material());
  // In-plane velocity gradient (stretch + shear + spin) in the patch plane.
  Eigen::Matrix2d L2;
  L2 << 0.3, 0.1, -0.05, -0.2;
  Mat3 L = Mat3::Zero();
  L.topLeftCorner<2, 2>() = L2;
  const Mat3 Lg = R * L * R.transpose();
  // Velocities v = L x on the mid-step geometry x^{n-1/2} = reference; positions x^n = x + dt/2 v,
  // so the strain rate the element sees (evaluated at x^{n-1/2}) is exactly sym(L).
  const double dt = 1e-6;
  for (int i = 0; i < mem.num_nodes(); ++i) {
    mem.velocities()[i] = Lg * mesh.nodes[i];
    mem.positions()[i] = mesh.nodes[i] + 0.5 * dt * mem.velocities()[i];
  }
  mem.compute_forces(dt);
  // Expected plane-stress increment: sigma = C : sym(L) dt in the plane.
  const auto& m = mem.material();
  const double C11 = m.youngs / (1 - m.poisson * m.poisson), C12 = m.poisson * C11;
  const double G = m.youngs / (2 * (1 + m.poisson));
  Mat3 s = Mat3::Zero();
  const double dxx = L2(0, 0), dyy = L2(1, 1), dxy = 0.5 * (L2(0, 1) + L2(1, 0));
  s(0, 0) = dt * (C11 * dxx + C12 * dyy);
  s(1, 1) = dt * (C12 * dxx + C11 * dyy);
  s(0, 1) = s(1, 0) = dt * 2 * G * dxy;
  const Mat3 expected = R * s * R.transpose();
  for (int e = 0; e < mem.num_elements(); ++e) {
    // The stress lives in the co-rotational frame of the mid-step geometry (the reference here).
    const auto& q = mesh.quads[e];
    const Mat3 fq = quad_frame({mesh.nodes[q[0]], mesh.nodes[q[1]], mesh.nodes[q[2]], mesh.nodes[q[3]]}).q;
    const Mat3 loc = fq.transpose() * expected * fq;
    const Eigen::Vector3d want(loc(0, 0), loc(1, 1), loc(0, 1));
    EXPECT_LT((mem.local_stress(e) - want).norm(), 1e-10 * expected.norm()) << "element " << e;
  }
  // Uniform stress: the interior nodes are in equilibrium, up to the frame change between
  // x^{n-1/2} and x^n (a rotation of order dt |L| = 3e-7 here).
  const double f_scale = expected.norm() * m.thickness * (1.0 / 3.0);
  for (int id : {5, 6, 9, 10}) EXPECT_LT(mem.forces()[id].norm(), 1e-5 * f_scale) << "node " << id;
}

TEST(Membrane, RigidMotionsGiveNoForceAndHourglassModesAreResisted) {
  const Mat3 R = (Eigen::AngleAxisd(0.7, Vec3(-1, 0.5, 2).normalized())).toRotationMatrix();
  QuadMesh mesh = rectangle_mesh(Vec3::Zero(), Vec3(0.1, 0, 0), Vec3(0.02, 0.09, 0), 1, 1);
  for (auto& x : mesh.nodes) x = R * x;
  auto make = [&] {
    auto m = material();
    m.hourglass_normal = 0.1;
    return Membrane(mesh.nodes, mesh.quads, m);
  };
  const double dt = 1e-4;
  const Vec3 c = 0.25 * (mesh.nodes[0] + mesh.nodes[1] + mesh.nodes[2] + mesh.nodes[3]);
  // Rigid translation and three rigid rotations: zero stress and zero nodal force.
  const Vec3 motions[4] = {Vec3(1, -2, 0.5), Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3)};
  for (int k = 0; k < 4; ++k) {
    Membrane mem = make();
    for (int i = 0; i < 4; ++i) {
      mem.velocities()[i] = k == 0 ? motions[0] : Vec3(motions[k].cross(mesh.nodes[i] - c));
      mem.positions()[i] = mesh.nodes[i] + 0.5 * dt * mem.velocities()[i];  // x^{n-1/2} = reference
    }
    mem.compute_forces(dt);
    for (int i = 0; i < 4; ++i) EXPECT_LT(mem.forces()[i].norm(), 1e-12) << "motion " << k << " node " << i;
    EXPECT_LT(mem.local_stress(0).norm(), 1e-12);
  }
  // Hourglass modes h = (1, -1, 1, -1) along local x, y and z: no strain rate but resisting force.
  const double h[4] = {1, -1, 1, -1};
  for (int a = 0; a < 3; ++a) {
    Membrane mem = make();
    const auto& ids = mesh.quads[0];
    const Mat3 q = quad_frame({mem.positions()[ids[0]], mem.positions()[ids[1]], mem.positions()[ids[2]],
                               mem.positions()[ids[3]]}).q;
    for (int i = 0; i < 4; ++i) mem.velocities()[ids[i]] = h[i] * q.col(a);
    mem.compute_forces(dt);
    double power = 0;
    for (int i = 0; i < 4; ++i) power += mem.forces()[i].dot(mem.velocities()[i]);
    EXPECT_LT(power, 0.0) << "hourglass mode along local axis " << a;
    EXPECT_GT(mem.energies().hourglass, 0.0);
    if (a < 2) {
      EXPECT_LT(mem.local_stress(0).norm(), 1e-6 * std::abs(power));
    }
  }
}

TEST(Membrane, PressurisedCylinderQuarterEquilibrium) {
  // Quarter of a long cylinder (plane strain along z), R0 = 1, t = 0.01, E = 1e6, nu = 0.3,
  // internal pressure p = 500, dynamic relaxation by mass-proportional damping.
  const double R0 = 1.0, p = 500;
  const int n = 16;
  std::vector<Eigen::Vector2d> arc;
  for (int i = 0; i <= n; ++i) arc.emplace_back(R0 * std::cos(0.5 * kPi * i / n), R0 * std::sin(0.5 * kPi * i / n));
  const QuadMesh mesh = extruded_polyline(arc, 0.0, 0.1, 1);
  Membrane mem(mesh.nodes, mesh.quads, material());
  mem.fix_where([](const Vec3&) { return true; }, {false, false, true});
  mem.fix_where([](const Vec3& x) { return std::abs(x[1]) < 1e-12; }, {false, true, false});  // symmetry y = 0
  mem.fix_where([](const Vec3& x) { return std::abs(x[0]) < 1e-9; }, {true, false, false});   // symmetry x = 0
  mem.set_pressure(p);
  mem.set_damping(60);  // about critical for the breathing mode (omega ~ 33 rad/s)
  const double dt = mem.critical_time_step();
  for (double t = 0; t < 1.0; t += dt) mem.step(dt);
  const auto& m = mem.material();
  // Predicted radius: hypo-elastic hoop stress sigma = E/(1-nu^2) ln(R/R0) (eps_zz = 0) and
  // sigma t = p R_mid with R_mid = R cos(dtheta/2) for the polygon (exact nodal equilibrium).
  const double cd = std::cos(0.25 * kPi / n);
  double R = R0;
  for (int it = 0; it < 100; ++it) R = R0 * std::exp(p * R * cd / (m.plate_modulus() * m.thickness));
  double worst_eq = 0, worst_r = 0;
  for (int e = 0; e < mem.num_elements(); ++e) {
    const auto& q = mesh.quads[e];
    const Vec3 mid = 0.25 * (mem.positions()[q[0]] + mem.positions()[q[1]] + mem.positions()[q[2]] + mem.positions()[q[3]]);
    const double Rmid = mid.head<2>().norm();
    const double hoop = mem.local_stress(e).head<2>().maxCoeff();
    worst_eq = std::max(worst_eq, std::abs(hoop * m.thickness / Rmid / p - 1));
  }
  for (int i = 0; i < mem.num_nodes(); ++i) worst_r = std::max(worst_r, std::abs(mem.positions()[i].head<2>().norm() / R - 1));
  std::printf("[cylinder] predicted R = %.6f; max |N/(R_mid p) - 1| = %.3e; max |R_node/R - 1| = %.3e\n", R, worst_eq,
              worst_r);
  EXPECT_LT(worst_eq, 1e-3);
  EXPECT_LT(worst_r, 1e-3);
  EXPECT_GT(R / R0 - 1, 0.04);  // the membrane did stretch (about 4.6 %)
}

TEST(Membrane, BadInputIsReported) {
  auto mesh = rectangle_mesh(Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1);
  auto m = material();
  m.thickness = 0;
  EXPECT_THROW(Membrane(mesh.nodes, mesh.quads, m), std::invalid_argument);
  mesh.quads[0][2] = 7;
  EXPECT_THROW(Membrane(mesh.nodes, mesh.quads, material()), std::invalid_argument);
  auto flat = rectangle_mesh(Vec3::Zero(), Vec3(1, 0, 0), Vec3(2, 0, 0), 1, 1);
  EXPECT_THROW(Membrane(flat.nodes, flat.quads, material()), std::runtime_error);
}

namespace {

/// Clamped 50 x 50 mm membrane (E = 7e10, rho = 750, t = 0.1 mm as in section 7.1) whose nodes
/// within 4.5 mm of the centre start at 10 m/s out of plane; no damping, no load.
Membrane point_impact_membrane() {
  const double half = 0.025;
  auto mesh = rectangle_mesh(Vec3(-half, -half, 0), Vec3(2 * half, 0, 0), Vec3(0, 2 * half, 0), 25, 25);
  auto m = material();
  m.rho = 750;
  m.youngs = 7e10;
  m.thickness = 1e-4;
  Membrane mem(mesh.nodes, mesh.quads, m);
  mem.fix_where([&](const Vec3& x) { return std::abs(std::abs(x[0]) - half) < 1e-9 || std::abs(std::abs(x[1]) - half) < 1e-9; },
                {true, true, true});
  for (int k = 0; k < mem.num_nodes(); ++k)
    if (mem.positions()[k].head<2>().norm() < 4.5e-3) mem.velocities()[k] = Vec3(0, 0, -10);
  return mem;
}

/// Kinetic + strain + hourglass energy [J].
double stored_energy(const Membrane& mem) {
  const auto e = mem.energies();
  return e.kinetic + e.strain + e.hourglass;
}

}  // namespace

TEST(Membrane, PointImpactConservesEnergy) {
  // The point impact: the stored energy must stay constant through large local deflections
  // (0.3 ms).
  Membrane mem = point_impact_membrane();
  const double e0 = stored_energy(mem);
  const double dt = mem.critical_time_step();
  double zmin = 0, worst = 0;
  for (double t = 0; t < 0.3e-3; t += dt) {
    mem.step(dt);
    worst = std::max(worst, std::abs(stored_energy(mem) / e0 - 1));
    for (const auto& x : mem.positions()) zmin = std::min(zmin, x[2]);
  }
  std::printf("[impact] max |E/E0 - 1| = %.3e, deepest point %.3f mm\n", worst, zmin * 1e3);
  EXPECT_GT(-zmin, 1e-4);  // about 0.2 mm: element rotations of order 0.1 rad
  EXPECT_LT(worst, 0.02);
}

TEST(Membrane, PointImpactConservesEnergyWithVaryingSteps) {
  // The impact above at 0.45 of the critical step (the ratio of the sphere-on-membrane example,
  // where the MPM sphere sets the step) with periodic step patterns: n full steps, then two
  // shorter ones, as a run that lands each output time by shortening its last steps would take.
  // Central differences with variable steps (section 3.2): velocities advance by
  // dt^n = (dt^{n-1/2} + dt^{n+1/2}) / 2, the strain by the last step dt^{n-1/2}. With dt^{n+1/2}
  // for both (the code before), patterns (20 steps, 2 x 0.6) and (7, 2 x 0.7) blew up.
  struct Pattern {
    int period, shorter;
    double factor;
  };
  for (const Pattern pat : {Pattern{20, 2, 0.6}, Pattern{7, 2, 0.7}}) {
    Membrane mem = point_impact_membrane();
    const double e0 = stored_energy(mem);
    const double dt = mem.critical_time_step(0.45);
    double worst = 0;
    long n = 0;
    for (double t = 0; t < 0.3e-3 && worst < 1; ++n) {
      const double h = n % pat.period < pat.period - pat.shorter ? dt : pat.factor * dt;
      ASSERT_NO_THROW(mem.step(h)) << "step " << n;
      t += h;
      worst = std::max(worst, std::abs(stored_energy(mem) / e0 - 1));
    }
    std::printf("[impact, %d steps then 2 x %.1f] max |E/E0 - 1| = %.3e over %ld steps\n", pat.period - pat.shorter,
                pat.factor, worst, n);
    EXPECT_LT(worst, 0.02);  // the same bound as with equal steps
  }
}
