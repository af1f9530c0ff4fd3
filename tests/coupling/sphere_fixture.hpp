#pragma once
/// @file sphere_fixture.hpp
/// A stiff sphere on springs in a large fluid box (benchmarks.md §2.1), shared by the test and
/// apps/bench/coupling. Exact: f = (1/2π)√(k/(m + ½ρ_f V)), V the meshed sphere volume.
#include <cmath>

#include "coupling/coupled_stepper.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"

namespace tetfsi::test {

struct SphereRun {
  double frequency = 0, exact = 0, discrete_volume = 0;
  int tets = 0;
};

// Sphere radius a = 0.1 m at the centre of the box [-b, b]³ whose walls are open (p = 0);
// the finite box changes the added mass by O((a/b)³) (0.8% at b = 5a).
inline SphereRun run_sphere(double edge_near, double edge_far, double periods) {
  const double a = 0.1, b = 0.5, rho = 1000, k = 400.0;
  mesh::MeshSizing sizing;
  sizing.edge_length = edge_far;
  sizing.edge_length_near_solids = edge_near;
  sizing.grading_distance = 0.25;
  sizing.facet_distance = 0.1 * edge_near;
  const mesh::TetMesh m = mesh::build_complex({-b, -b, -b}, {b, b, b}, {mesh::make_sphere(a, 3)}, sizing);

  fluid::FluidParams fp;
  fp.density = rho;
  fp.gravity = Eigen::Vector3d::Zero();
  fp.apply_gravity = false;
  solid::TetMaterial mat;
  mat.density = rho;
  mat.youngs_modulus = 1e8;  // rigid compared with the 2 Hz mode
  mat.poisson_ratio = 0.3;
  coupling::CoupledSettings cs;
  cs.time_step = 1.0 / 100;
  cs.newmark = solid::NewmarkScheme::kTrapezoidal;
  coupling::CoupledStepper stepper(m, fp, {mat}, cs);
  fluid::BoundaryPatch open;
  open.kind = fluid::FaceKind::kOpen;
  open.region.lo = Eigen::Vector3d::Constant(-2 * b);
  open.region.hi = Eigen::Vector3d::Constant(2 * b);  // every outer face
  stepper.fluid_boundary().patches.push_back(open);

  auto& sphere = stepper.solid(0);
  const solid::TetModel& model = stepper.solid_model(0);
  SphereRun run;
  for (int t = 0; t < model.num_tets(); ++t) run.discrete_volume += model.rest_volume(t);
  const Eigen::VectorXd& X = model.reference_positions();
  for (int node = 0; node < model.num_nodes(); ++node)
    sphere.add_spring({node, X.segment<3>(3 * node), k / model.num_nodes()});
  sphere.set_uniform_velocity({1e-3, 0, 0});
  const double mass = rho * run.discrete_volume;
  run.exact = std::sqrt(k / (mass + 0.5 * rho * run.discrete_volume)) / (2 * M_PI);
  run.tets = m.num_tets();

  const int steps = static_cast<int>(periods / (run.exact * cs.time_step));
  double prev = 0, first = -1, last = -1;
  int crossings = 0;
  for (int s = 0; s < steps; ++s) {
    stepper.step();
    const Eigen::VectorXd& d = sphere.displacement();
    double x = 0;
    for (int node = 0; node < model.num_nodes(); ++node) x += d[3 * node] / model.num_nodes();
    if (s > 0 && prev < 0 && x >= 0) {
      const double tc = stepper.time() - cs.time_step * x / (x - prev);
      if (first < 0) first = tc;
      last = tc;
      ++crossings;
    }
    prev = x;
  }
  if (crossings >= 2) run.frequency = (crossings - 1) / (last - first);
  return run;
}


}  // namespace tetfsi::test
