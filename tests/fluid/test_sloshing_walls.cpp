// The sloshing tank of issue 41 keeps its energy and is the same at its two side walls.
//
// Tank 0.8 m long (x), 0.1 m wide (z), still depth H = 0.3 m, gravity -y; the first mode started
// with a 5 mm cosine surface, inviscid, h = 1/40 s, ten periods of the linear-theory frequency
// (f = 0.89825 Hz, omega^2 = g k tanh(k H), k = pi / L). The mesh is CGAL's mesh of half the tank's
// width (edge 0.02 m) and its mirror image about the mid-plane z = W/2: mesh, liquid and gravity are
// mirror symmetric, so the exact discrete solution is too, and only the order of floating-point
// sums and the pressure solver's tolerance (1e-10 relative residual) may tell the halves apart.
// Before, the clamping of back-traces that leave through a wall depended on where the point
// location's walk started (the node's lowest-numbered tet, numbered along a space-filling curve
// from the low corner), and the cut-tet quads were split along the diagonal from the lower
// node id: the level set differed by 1.3e-4 m between the halves after 0.5 s, and a tongue of
// liquid climbed the z = 0 wall alone, 10 mm above the interior by t = 3 s, while the wave's
// energy rose to 2.8 times its start.
//
// Asserted:
//  - symmetry: phi at every node equals phi at its mirror node to 1e-6 m (2e-4 of the amplitude);
//  - the wave is two-dimensional: at both side walls the surface stays within 1 mm (a fifth of the
//    amplitude, 0.05 of the edge) of the first mode fitted to the whole surface;
//  - energy: E = kinetic + gravitational - that of the same liquid at rest. The projection removes
//    kinetic energy and never adds it; the step moves the surface with the start-of-step velocity
//    and then the velocity with the moved surface, as symplectic Euler does for the oscillator
//    eta'' = -omega^2 eta, whose energy swings by about omega h / 2 within a period and returns.
//    So E may exceed its start by at most omega h (0.14) at any step, and its largest value over
//    the last period may not exceed that over the first.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "fluid/fluid_solver.hpp"
#include "fluid/liquid/level_set.hpp"
#include "mesh/complex_mesher.hpp"

namespace tetfsi::fluid {
namespace {

/// CGAL's mesh of [lo, hi] with hi.z the mid-plane, and its mirror image about that plane (the
/// vertices on it shared).
mesh::TetMesh mirrored_half_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double edge) {
  mesh::MeshSizing sizing;
  sizing.edge_length = edge;
  const mesh::TetMesh half = mesh::build_complex(lo, hi, {}, sizing);
  mesh::TetMesh m = half;
  std::vector<int> image(half.num_vertices());
  for (int v = 0; v < half.num_vertices(); ++v) {
    Eigen::Vector3d y = half.vertices[v];
    if (std::abs(y.z() - hi.z()) < 1e-12) {
      image[v] = v;
      continue;
    }
    y.z() = 2 * hi.z() - y.z();
    image[v] = m.num_vertices();
    m.vertices.push_back(y);
  }
  for (int t = 0; t < half.num_tets(); ++t) {
    std::array<int, 4> tet = half.tets[t];
    for (int& v : tet) v = image[v];
    std::swap(tet[0], tet[1]);  // a mirror image turns the orientation
    m.tets.push_back(tet);
    m.subdomain.push_back(half.subdomain[t]);
  }
  return m;
}

/// For each node of `mesh`, the node at its mirror position about z = z_mid (-1 if none).
std::vector<int> mirror_nodes(const FluidMesh& mesh, double z_mid) {
  auto key = [](const Eigen::Vector3d& x) {
    return std::make_tuple(std::llround(x.x() * 1e9), std::llround(x.y() * 1e9), std::llround(x.z() * 1e9));
  };
  std::map<std::tuple<long long, long long, long long>, int> at;
  for (int i = 0; i < mesh.num_nodes(); ++i) at[key(mesh.nodes[i])] = i;
  std::vector<int> mirror(mesh.num_nodes(), -1);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    Eigen::Vector3d y = mesh.nodes[i];
    y.z() = 2 * z_mid - y.z();
    if (const auto it = at.find(key(y)); it != at.end()) mirror[i] = it->second;
  }
  return mirror;
}

TEST(FreeSurface, SloshingTankKeepsItsEnergyAndIsTheSameAtBothSideWalls) {
  const double L = 0.8, W = 0.1, H = 0.3, a = 0.005, g = 9.81, rho = 1000.0, pi = std::acos(-1.0), k = pi / L;
  const double omega = std::sqrt(g * k * std::tanh(k * H)), h = 1.0 / 40;
  const int steps = static_cast<int>(std::lround(10 * 2 * pi / omega / h));
  const mesh::TetMesh m = mirrored_half_box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(L, 0.36, W / 2), 0.02);
  FluidParams params;
  params.density = rho;
  params.gravity = Eigen::Vector3d(0, -g, 0);
  params.solver.tolerance = 1e-10;
  FluidSolver solver(params);
  solver.initialize(m);
  LiquidOptions liquid;
  liquid.band = 4 * solver.mesh().mean_edge_length();
  solver.set_liquid(sample_level_set(solver.mesh(), [&](const Eigen::Vector3d& x) { return x.y() - H - a * std::cos(k * x.x()); }),
                    liquid);
  const std::vector<int> mirror = mirror_nodes(solver.mesh(), W / 2);
  ASSERT_EQ(std::count(mirror.begin(), mirror.end(), -1), 0);
  // The gravitational energy of the liquid at rest: a layer of depth V / (W L).
  const double V = solver.target_liquid_volume(), rest = rho * g * V * V / (2 * W * L);
  auto wave_energy = [&](const StepReport& r) { return r.kinetic_energy + r.gravity_potential - rest; };
  StepReport start;
  solver.report_energies(start);
  const double E0 = wave_energy(start);
  ASSERT_NEAR(E0, 0.25 * rho * g * a * a * L * W, 0.05 * E0);  // 1/2 rho g W int eta^2 dx
  const int per_period = static_cast<int>(std::lround(2 * pi / omega / h));
  double asymmetry = 0, wall_offset[2] = {0, 0}, first_period_max = 0, last_period_max = 0, largest = 0;
  for (int s = 1; s <= steps; ++s) {
    const StepReport r = solver.step(m, {}, h);
    const Eigen::VectorXd& phi = solver.level_set();
    for (int i = 0; i < phi.size(); ++i) asymmetry = std::max(asymmetry, std::abs(phi[i] - phi[mirror[i]]));
    // The first mode fitted to the surface, and the walls' zero-set vertices against it.
    const mesh::SurfaceMesh surface = zero_set(solver.mesh(), phi);
    double num = 0, den = 0;
    for (const auto& x : surface.vertices) {
      num += (x.y() - H) * std::cos(k * x.x());
      den += std::cos(k * x.x()) * std::cos(k * x.x());
    }
    const double A = num / den;
    for (const auto& x : surface.vertices)
      for (int wall = 0; wall < 2; ++wall)
        if (std::abs(x.z() - wall * W) < 1e-9)
          wall_offset[wall] = std::max(wall_offset[wall], std::abs(x.y() - H - A * std::cos(k * x.x())));
    const double E = wave_energy(r);
    largest = std::max(largest, E);
    if (s <= per_period) first_period_max = std::max(first_period_max, E);
    if (s > steps - per_period) last_period_max = std::max(last_period_max, E);
    ASSERT_LE(asymmetry, 1e-6) << "t = " << s * h << " s: the two halves differ";
    ASSERT_LE(E, (1 + omega * h) * E0) << "t = " << s * h << " s: the wave gained energy";
  }
  std::printf("sloshing tank, %d tets, %d steps: max |phi - phi(mirror)| %.2e m, surface at the walls within "
              "%.2e / %.2e m of the fitted mode, energy: largest %.4f, last period's largest %.4f, first period's "
              "%.4f of the start\n",
              solver.mesh().num_tets(), steps, asymmetry, wall_offset[0], wall_offset[1], largest / E0,
              last_period_max / E0, first_period_max / E0);
  EXPECT_LE(wall_offset[0], 1e-3);
  EXPECT_LE(wall_offset[1], 1e-3);
  EXPECT_LE(last_period_max, first_period_max);
}

}  // namespace
}  // namespace tetfsi::fluid
