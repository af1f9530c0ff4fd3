// FluidSolver steps: buoyancy (exact cancellation of a stratified force, sign of a hot blob), vorticity
// confinement, an inflow emitter carrying smoke to an open boundary, determinism, NaN detection.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "fluid/fluid_solver.hpp"
#include "fluid_test_support.hpp"

namespace tetfsi::fluid {
namespace {

const Eigen::Vector3d kLo(0, 0, 0), kHi(1, 1, 1);

/// Sets the velocity of every tet of `s` to (sin 3y, cos 2z, x) at its centroid [m/s].
void swirl(FluidSolver& s) {
  for (int t = 0; t < s.mesh().num_tets(); ++t) {
    const Eigen::Vector3d c = s.mesh().centroid(t);
    s.fields().velocity[t] = Eigen::Vector3d(std::sin(3 * c.y()), std::cos(2 * c.z()), c.x());
  }
}

TEST(FluidSolver, StratifiedBuoyancyIsBalancedByPressure) {
  // T constant on each layer of cells (T = T0 + 10 k/6 on layer k): the Boussinesq force
  // beta (T - T0) e_z is the gradient of a potential that is continuous and linear in z on each layer,
  // i.e. a P1 function on this mesh, so the projection cancels it exactly: u stays 0.
  const mesh::TetMesh m = mesh::structured_box(kLo, kHi, 6, 6, 6);
  FluidParams p;
  p.apply_gravity = false;
  p.buoyancy.beta = 0.5;
  p.buoyancy.ambient_temperature = 300.0;
  p.solver.tolerance = 1e-12;
  FluidSolver s(p);
  s.initialize(m);
  for (int t = 0; t < s.mesh().num_tets(); ++t) s.fields().temperature[t] = 300.0 + 10.0 * std::round(s.mesh().centroid(t).z() * 6 - 0.5) / 6;
  const StepReport r = s.step(m, {}, 0.01);
  double umax = 0.0;
  for (const auto& u : s.fields().velocity) umax = std::max(umax, u.norm());
  EXPECT_LT(umax, 1e-9 * 0.01 * 0.5 * 10.0) << "max |u| " << umax;
  EXPECT_LE(r.max_divergence, 1e-8 * 1.0 / (1.0 / 6));
}

TEST(FluidSolver, HotBlobRisesAndSmokySinks) {
  const mesh::TetMesh m = mesh::structured_box(kLo, kHi, 6, 6, 6);
  for (double sign : {1.0, -1.0}) {
    FluidParams p;
    p.apply_gravity = false;
    p.buoyancy.beta = 1.0;
    p.buoyancy.alpha = 1.0;
    FluidSolver s(p);
    s.initialize(m);
    double blob_w = 0.0, blob_v = 0.0;
    BoundaryConditions bc;
    SourceVolume src;
    src.region = {Eigen::Vector3d(0.3, 0.3, 0.3), Eigen::Vector3d(0.7, 0.7, 0.7)};
    src.temperature = sign > 0 ? 10.0 : 0.0;  // hot blob
    src.smoke = sign > 0 ? 0.0 : 10.0;        // or smoky (heavy) blob
    bc.sources = {src};
    s.step(m, bc, 0.02);
    for (int t = 0; t < s.mesh().num_tets(); ++t)
      if (src.region.contains(s.mesh().centroid(t))) {
        blob_w += s.mesh().volume[t] * s.fields().velocity[t].z();
        blob_v += s.mesh().volume[t];
      }
    ASSERT_GT(blob_v, 0.0);
    EXPECT_GT(sign * blob_w / blob_v, 0.01) << (sign > 0 ? "hot blob must rise" : "smoky blob must sink");
  }
}

TEST(FluidSolver, VorticityConfinementAddsEnergyToAVortexOnly) {
  const mesh::TetMesh m = mesh::structured_box(kLo, kHi, 8, 8, 2);
  const FluidMesh fm = build_fluid_mesh(m);
  TetVectors vortex(fm.num_tets()), uniform(fm.num_tets(), Eigen::Vector3d(1, 0.5, 0));
  for (int t = 0; t < fm.num_tets(); ++t) {
    const Eigen::Vector3d c = fm.centroid(t) - Eigen::Vector3d(0.5, 0.5, 0);
    vortex[t] = std::exp(-20 * c.squaredNorm()) * Eigen::Vector3d(-c.y(), c.x(), 0);
  }
  const double e0 = kinetic_energy(fm, vortex);
  add_vorticity_confinement(fm, 0.5, 0.05, vortex);
  EXPECT_GT(kinetic_energy(fm, vortex), e0);
  const TetVectors u0 = uniform;
  add_vorticity_confinement(fm, 0.5, 0.05, uniform);
  for (int t = 0; t < fm.num_tets(); ++t) EXPECT_LE((uniform[t] - u0[t]).norm(), 1e-12);
}

TEST(FluidSolver, InflowEmitterCarriesSmokeToTheOpenBoundary) {
  // Inflow U = 1 m/s with smoke 1 at x = 0, open at x = 1: uniform flow (exact in P1), the smoke front
  // reaches x = U t = 0.5 after 10 steps of 0.05 s.
  const mesh::TetMesh base = mesh::structured_box(kLo, kHi, 10, 4, 4);
  std::mt19937 rng(3);
  FluidParams p;
  p.apply_gravity = false;
  FluidSolver s(p);
  s.initialize(base);
  BoundaryConditions bc;
  BoundaryPatch in;
  in.region = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1, 1)};
  in.kind = FaceKind::kInflow;
  in.velocity = Eigen::Vector3d(1, 0, 0);
  in.smoke = 1.0;
  BoundaryPatch out;
  out.region = {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 1)};
  out.kind = FaceKind::kOpen;
  bc.patches = {in, out};
  for (int k = 0; k < 10; ++k) {
    const StepReport r = s.step(testing::jittered(base, kLo, kHi, 0.1, 0.1, rng), bc, 0.05);
    ASSERT_LE(r.max_divergence, 1e-8 / 0.1);
  }
  for (int t = 0; t < s.mesh().num_tets(); ++t) {
    const double x = s.mesh().centroid(t).x();
    ASSERT_LE((s.fields().velocity[t] - Eigen::Vector3d(1, 0, 0)).norm(), 1e-6);
    if (x < 0.35) {
      EXPECT_GT(s.fields().smoke[t], 0.9) << "x = " << x;
    }
    if (x > 0.65) {
      EXPECT_LT(s.fields().smoke[t], 0.1) << "x = " << x;
    }
  }
}

TEST(FluidSolver, SameInputSameOutput) {
  auto run = [] {
    const mesh::TetMesh base = mesh::structured_box(kLo, kHi, 6, 6, 6);
    std::mt19937 rng(8);
    FluidSolver s(FluidParams{});
    s.initialize(base);
    swirl(s);
    for (int k = 0; k < 3; ++k) s.step(testing::jittered(base, kLo, kHi, 1.0 / 6, 0.1, rng), {}, 0.05);
    return s.fields().velocity;
  };
  const TetVectors a = run(), b = run();
  for (size_t t = 0; t < a.size(); ++t) ASSERT_EQ(a[t], b[t]) << t;
}

TEST(FluidSolver, ACopySharesTheMeshAndKeepsItsStateWhileTheOriginalSteps) {
  // A copy of the solver shares the mesh; while it does, the original's steps build their moved
  // meshes elsewhere (the spare of the step before, reused from the second step on) instead of
  // moving the mesh in place, so the copy keeps its mesh and fields, and then steps exactly as
  // the original did. The reused spare gets the geometry a fresh copy of the mesh would.
  const mesh::TetMesh base = mesh::structured_box(kLo, kHi, 5, 5, 5);
  FluidSolver s(FluidParams{});
  s.initialize(base);
  swirl(s);
  const FluidSolver copy = s;
  EXPECT_EQ(&copy.mesh(), &s.mesh()) << "the copy shares the mesh";
  const FluidMesh mesh_before = s.mesh();
  const TetVectors velocity_before = s.fields().velocity;
  std::vector<mesh::TetMesh> moved;
  std::mt19937 rng(5);
  for (int k = 0; k < 3; ++k) moved.push_back(testing::jittered(base, kLo, kHi, 1.0 / 5, 0.1, rng));
  for (const mesh::TetMesh& m : moved) s.step(m, {}, 0.05);
  EXPECT_EQ(copy.mesh().nodes, mesh_before.nodes);
  EXPECT_EQ(copy.mesh().volume, mesh_before.volume);
  EXPECT_EQ(copy.fields().velocity, velocity_before);
  FluidMesh expected = mesh_before;
  update_fluid_mesh_geometry(moved.back(), expected);
  EXPECT_EQ(s.mesh().volume, expected.volume);
  EXPECT_EQ(s.mesh().dual_volume, expected.dual_volume);
  for (int t = 0; t < expected.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) ASSERT_EQ(s.mesh().grad[t][k], expected.grad[t][k]) << "tet " << t;
  FluidSolver again = copy;
  for (const mesh::TetMesh& m : moved) again.step(m, {}, 0.05);
  EXPECT_EQ(again.fields().velocity, s.fields().velocity);
}

TEST(FluidSolver, AMeshMovedInPlaceIsUndoneBitForBit) {
  // With nothing else holding the mesh, a step onto the mesh moved moves the one fluid mesh in
  // place (no second mesh); the undo point taken before it keeps the node positions, and undo()
  // gives back the mesh's geometry and the fields bit for bit, after which the step repeats exactly.
  const mesh::TetMesh base = mesh::structured_box(kLo, kHi, 5, 5, 5);
  FluidSolver s(FluidParams{});
  s.initialize(base);
  swirl(s);
  std::mt19937 rng(7);
  const mesh::TetMesh moved = testing::jittered(base, kLo, kHi, 1.0 / 5, 0.1, rng);
  const FluidMesh mesh_before = s.mesh();
  const FluidFields fields_before = s.fields();
  const FluidMesh* storage = &s.mesh();
  FluidSolver::UndoPoint undo = s.undo_point(moved);
  EXPECT_FALSE(undo.nodes.empty()) << "the undo point holds node positions, not the mesh";
  s.predict(moved, {}, 0.05);
  EXPECT_EQ(&s.mesh(), storage) << "moved in place";
  FluidMesh expected = mesh_before;
  update_fluid_mesh_geometry(moved, expected);
  EXPECT_EQ(s.mesh().nodes, expected.nodes);
  EXPECT_EQ(s.mesh().volume, expected.volume);
  EXPECT_NE(s.fields().velocity, fields_before.velocity) << "the step changed the fields";
  const TetVectors predicted = s.fields().velocity;
  s.undo(std::move(undo));
  EXPECT_EQ(s.mesh().nodes, mesh_before.nodes);
  EXPECT_EQ(s.mesh().volume, mesh_before.volume);
  EXPECT_EQ(s.mesh().dual_volume, mesh_before.dual_volume);
  for (int t = 0; t < mesh_before.num_tets(); ++t)
    for (int k = 0; k < 4; ++k) ASSERT_EQ(s.mesh().grad[t][k], mesh_before.grad[t][k]) << "tet " << t;
  for (std::size_t f = 0; f < mesh_before.boundary_faces.size(); ++f) {
    ASSERT_EQ(s.mesh().boundary_faces[f].normal, mesh_before.boundary_faces[f].normal);
    ASSERT_EQ(s.mesh().boundary_faces[f].area, mesh_before.boundary_faces[f].area);
  }
  EXPECT_EQ(s.fields().velocity, fields_before.velocity);
  EXPECT_EQ(s.fields().smoke, fields_before.smoke);
  EXPECT_EQ(s.fields().temperature, fields_before.temperature);
  s.predict(moved, {}, 0.05);
  EXPECT_EQ(s.fields().velocity, predicted);
}

TEST(FluidSolver, NaNAndBadInputAreErrors) {
  const mesh::TetMesh m = mesh::structured_box(kLo, kHi, 3, 3, 3);
  FluidSolver s(FluidParams{});
  s.initialize(m);
  s.fields().velocity[5].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(s.project_only({}, 0.1), SolverError);
  EXPECT_THROW(s.step(m, {}, -1.0), std::invalid_argument);
  FluidFields wrong;
  wrong.velocity.assign(3, Eigen::Vector3d::Zero());
  EXPECT_THROW(s.initialize(m, wrong), std::invalid_argument);
  FluidParams bad;
  bad.density = 0.0;
  EXPECT_THROW(FluidSolver{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace tetfsi::fluid
