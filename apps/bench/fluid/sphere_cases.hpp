#pragma once
/// @file sphere_cases.hpp
/// The two sphere validation cases shared by tests/fluid/test_sphere_flow.cpp (small meshes) and
/// bench_fluid (finer meshes): potential flow past a fixed sphere and the added mass of an
/// oscillating sphere. Meshes come from mesh::build_complex (CGAL), sphere = solid_subdomain(0).
#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/primitives.hpp"

namespace tetfsi::fluid::validation {

/// Box [-L, L]^3 with a sphere of radius a at the origin; edge h_near at the sphere, h_far away.
inline mesh::TetMesh sphere_in_box(double a, double L, double h_near, double h_far) {
  mesh::MeshSizing sz;
  sz.edge_length = h_far;
  sz.edge_length_near_solids = h_near;
  sz.grading_distance = 2.0 * a;
  return mesh::build_complex(Eigen::Vector3d::Constant(-L), Eigen::Vector3d::Constant(L), {mesh::make_sphere(a, 4)},
                             sz);
}

/// Potential flow of speed U along +x past a sphere of radius a at the origin:
/// u = U e_x + (U a^3 / 2) (e_x / r^3 - 3 x r / r^5)  (phi = U x (1 + a^3 / (2 r^3))).
inline Eigen::Vector3d potential_flow_velocity(const Eigen::Vector3d& r, double a, double U) {
  const double d = r.norm();
  return U * Eigen::Vector3d::UnitX() +
         0.5 * U * a * a * a * (Eigen::Vector3d::UnitX() / std::pow(d, 3) - 3.0 * r.x() * r / std::pow(d, 5));
}

struct PotentialFlowResult {
  int tets = 0;
  int nodes = 0;              ///< fluid nodes: the pressure unknowns
  double h_surface = 0;       ///< mean edge of the interface triangles [m]
  double surface_rms = 0;     ///< area-weighted rms of C_p(face) - (1 - 9/4 sin^2 theta)
  double surface_max = 0;
  double centroid_rms = 0;    ///< rms of C_p at the adjacent tet centroids vs exact potential flow there
  double cp_stagnation = 0;   ///< C_p of the most upstream face (exact 1)
  double cp_equator = 0;      ///< mean C_p of faces with |cos theta| < 0.1 (exact -1.25)
  double max_div_scaled = 0;  ///< max|div| h / U
  double seconds = 0;         ///< projection only
};

/// `m` = sphere_in_box(a, L, ...). One projection of u* = U e_x (irrotational, so the projection returns the potential flow) with the
/// exact far field imposed as the normal velocity on all six box faces (BoundaryConditions::
/// balance_inflow removes the O(h^2) quadrature imbalance): the truncated box then has the unbounded
/// solution, no blockage correction needed. C_p = 1 - |u_t|^2 / U^2 from the tet next to each
/// interface face; theta measured from the upstream axis.
inline PotentialFlowResult potential_flow(const mesh::TetMesh& m, double a, double L) {
  const double U = 1.0;
  FluidParams p;
  p.apply_gravity = false;
  p.solver.tolerance = 1e-12;
  FluidSolver s(p);
  s.initialize(m);
  for (auto& u : s.fields().velocity) u = Eigen::Vector3d(U, 0, 0);
  BoundaryConditions bc;
  BoundaryPatch far;
  far.region = {Eigen::Vector3d::Constant(-L), Eigen::Vector3d::Constant(L)};
  far.kind = FaceKind::kInflow;
  far.velocity_field = [a, U](const Eigen::Vector3d& x) -> Eigen::Vector3d { return potential_flow_velocity(x, a, U); };
  bc.patches = {far};
  bc.balance_inflow = true;
  const StepReport rep = s.project_only(bc, 1.0);
  PotentialFlowResult r;
  r.tets = m.num_tets();
  r.nodes = static_cast<int>(s.mesh().nodes.size());
  r.seconds = rep.assemble_seconds + rep.solve_seconds;
  const FluidMesh& fm = s.mesh();
  double area = 0, sum2 = 0, csum2 = 0, eq = 0, edge = 0, upstream = 1e300;
  int neq = 0, nface = 0;
  for (const BoundaryFace& bf : fm.boundary_faces) {
    if (bf.other_subdomain != mesh::solid_subdomain(0)) continue;
    const Eigen::Vector3d c = (fm.nodes[bf.nodes[0]] + fm.nodes[bf.nodes[1]] + fm.nodes[bf.nodes[2]]) / 3.0;
    const double cos_t = c.x() / c.norm();
    const double cp = 1.0 - s.fields().velocity[bf.tet].squaredNorm() / (U * U);
    const double err = cp - (1.0 - 2.25 * (1.0 - cos_t * cos_t));
    const double cp_exact_centroid = 1.0 - potential_flow_velocity(fm.centroid(bf.tet), a, U).squaredNorm() / (U * U);
    area += bf.area;
    sum2 += bf.area * err * err;
    csum2 += bf.area * std::pow(cp - cp_exact_centroid, 2);
    r.surface_max = std::max(r.surface_max, std::abs(err));
    if (c.x() < upstream) {
      upstream = c.x();
      r.cp_stagnation = cp;
    }
    if (std::abs(cos_t) < 0.1) {
      eq += cp;
      ++neq;
    }
    for (int k = 0; k < 3; ++k) edge += (fm.nodes[bf.nodes[k]] - fm.nodes[bf.nodes[(k + 1) % 3]]).norm();
    nface += 3;
  }
  r.surface_rms = std::sqrt(sum2 / area);
  r.centroid_rms = std::sqrt(csum2 / area);
  r.cp_equator = neq ? eq / neq : 0.0;
  r.h_surface = edge / nface;
  r.max_div_scaled = rep.max_divergence * r.h_surface / U;
  return r;
}

struct AddedMassResult {
  int tets = 0;
  double measured = 0;   ///< least-squares m in F = -m x'' over one period [kg]
  double impulsive = 0;  ///< m from the impulsive start: one projection from rest, F = -m V / dt [kg]
  double ideal = 0;      ///< 1/2 rho V (V = meshed sphere volume) [kg]
  double max_div_scaled = 0;
  double seconds = 0;    ///< all steps
};

/// `m` = sphere_in_box(a, L, ...). Sphere of radius a oscillating as x(t) = A sin(w t), A = 0.01 a, w = 2 pi, in water (rho = 1000)
/// at rest far away. The mesh stays fixed (A << h: linearised kinematics, the interface faces carry
/// the solid velocity V(t)). The box faces carry the exact unbounded far field of the moving sphere,
/// u = grad(-(V a^3 / 2) x / r^3) = -(V a^3 / 2)(e_x / r^3 - 3 x r / r^5) (balanced as in potential_flow), so the reference is the
/// unbounded added mass 1/2 rho V. The projection's pressure is rho dphi/dt at mid-step, so the force
/// of step n+1 is compared with x'' at t_n + dt/2. steps_per_period = 0: impulsive start only.
inline AddedMassResult added_mass(const mesh::TetMesh& m, double a, double L, int steps_per_period,
                                  AdvectionScheme scheme = AdvectionScheme::kLinear) {
  const double rho = 1000.0, A = 0.01 * a, w = 2.0 * std::acos(-1.0), dt = 1.0 / std::max(1, steps_per_period);
  double volume = 0;
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.subdomain[t] == mesh::solid_subdomain(0)) volume += mesh::signed_volume(m, t);
  FluidParams p;
  p.density = rho;
  p.apply_gravity = false;
  p.solver.tolerance = 1e-10;
  p.advection = scheme;
  FluidSolver s(p);
  s.initialize(m);
  BoundaryConditions bc;
  bc.balance_inflow = true;
  BoundaryPatch far;
  far.region = {Eigen::Vector3d::Constant(-L), Eigen::Vector3d::Constant(L)};
  far.kind = FaceKind::kInflow;
  auto set_velocity = [&](double t) {
    const double v = A * w * std::cos(w * t);
    bc.solid_vertex_velocity.assign(m.num_vertices(), Eigen::Vector3d(v, 0, 0));
    far.velocity_field = [a, v](const Eigen::Vector3d& x) -> Eigen::Vector3d {
      // Lab frame = flow past a fixed sphere at U = -v, plus v e_x: the pure dipole.
      return potential_flow_velocity(x, a, -v) + Eigen::Vector3d(v, 0, 0);
    };
    bc.patches = {far};
  };
  set_velocity(0.0);
  s.project_only(bc, dt);
  AddedMassResult r;
  r.impulsive = -s.pressure_force(mesh::solid_subdomain(0)).x() * dt / (A * w);
  r.tets = m.num_tets();
  double fa = 0, aa = 0, h = s.mesh().mean_edge_length();
  const auto t0 = std::chrono::steady_clock::now();
  for (int n = 1; n <= steps_per_period; ++n) {
    const double t = n * dt;
    set_velocity(t);
    const StepReport rep = s.step(m, bc, dt);
    r.max_div_scaled = std::max(r.max_div_scaled, rep.max_divergence * h / (A * w));
    const double acc = -A * w * w * std::sin(w * (t - 0.5 * dt));
    fa += s.pressure_force(mesh::solid_subdomain(0)).x() * acc;
    aa += acc * acc;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.measured = aa > 0 ? -fa / aa : r.impulsive;
  r.ideal = 0.5 * rho * volume;
  return r;
}

}  // namespace tetfsi::fluid::validation
