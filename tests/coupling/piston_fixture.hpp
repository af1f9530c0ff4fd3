#pragma once
/// @file piston_fixture.hpp
/// The piston of shared/references/benchmarks.md §6 as a coupled scene: a tube [0, L + ℓ] x [0, w]²
/// meshed with structured tets; the fluid column [0, L] is open (p = 0) at x = 0, the solid plug
/// [L, L + ℓ] is held by springs of total stiffness k on its far face. The walls are frictionless.
/// Exact frequency of the coupled system: f = (1/2π) √(k / (m_s + ρ_f L A)).
#include <cmath>
#include <memory>

#include "coupling/coupled_stepper.hpp"
#include "mesh/structured_box.hpp"

namespace tetfsi::test {

struct PistonSetup {
  double length = 1.0;          ///< fluid column L [m]
  double plug = 0.1;            ///< plug length ℓ [m]
  double width = 0.1;           ///< tube side w [m], A = w²
  int cells_per_metre = 10;     ///< along the tube
  double fluid_density = 1000;  ///< ρ_f [kg/m³]
  double solid_density = 1000;  ///< ρ_s [kg/m³]
  double youngs_modulus = 1e9;  ///< stiff: the plug's own modes are ~kHz
  double spring = 1000;         ///< k [N/m]
  double time_step = 1.0 / 200;
  coupling::CouplingScheme scheme = coupling::CouplingScheme::kSimultaneous;
  coupling::CoupledSolverKind solver = coupling::CoupledSolverKind::SchurCG;
  solid::NewmarkScheme newmark = solid::NewmarkScheme::kTrapezoidal;

  double area() const { return width * width; }
  double solid_mass() const { return solid_density * area() * plug; }
  double added_mass() const { return fluid_density * length * area(); }
  double exact_frequency() const { return std::sqrt(spring / (solid_mass() + added_mass())) / (2 * M_PI); }
};

inline std::unique_ptr<coupling::CoupledStepper> make_piston(const PistonSetup& s, double initial_velocity) {
  const int nf = static_cast<int>(std::lround(s.length * s.cells_per_metre));
  const int ns = std::max(1, static_cast<int>(std::lround(s.plug * s.cells_per_metre)));
  mesh::TetMesh m = mesh::structured_box({0, 0, 0}, {s.length + s.plug, s.width, s.width}, nf + ns, 1, 1);
  for (int t = 0; t < m.num_tets(); ++t) {
    double cx = 0;
    for (int v : m.tets[t]) cx += m.vertices[v].x() / 4;
    m.subdomain[t] = cx > s.length ? mesh::solid_subdomain(0) : mesh::kFluidSubdomain;
  }
  fluid::FluidParams fp;
  fp.density = s.fluid_density;
  fp.gravity = Eigen::Vector3d::Zero();
  fp.apply_gravity = false;
  solid::TetMaterial mat;
  mat.density = s.solid_density;
  mat.youngs_modulus = s.youngs_modulus;
  mat.poisson_ratio = 0.3;
  coupling::CoupledSettings cs;
  cs.time_step = s.time_step;
  cs.scheme = s.scheme;
  cs.solver = s.solver;
  cs.newmark = s.newmark;
  auto stepper = std::make_unique<coupling::CoupledStepper>(m, fp, std::vector<solid::TetMaterial>{mat}, cs);

  fluid::BoundaryPatch open;
  open.kind = fluid::FaceKind::kOpen;
  open.region.lo = {-1e-9, -1, -1};
  open.region.hi = {1e-9, 2, 2};
  stepper->fluid_boundary().patches.push_back(open);

  auto& plug = stepper->solid(0);
  const auto far = plug.nodes_in_box({s.length + s.plug - 1e-9, -1, -1}, {s.length + s.plug + 1e-9, 2, 2});
  const auto& X = stepper->solid_model(0).reference_positions();
  for (int node : far) plug.add_spring({node, X.segment<3>(3 * node), s.spring / far.size()});
  plug.set_uniform_velocity({initial_velocity, 0, 0});
  return stepper;
}

/// Mean x-displacement of the plug [m].
inline double plug_displacement(coupling::CoupledStepper& stepper) {
  const Eigen::VectorXd& d = stepper.solid(0).displacement();
  double sum = 0;
  for (int a = 0; a < d.size() / 3; ++a) sum += d[3 * a];
  return sum / (d.size() / 3);
}

}  // namespace tetfsi::test
