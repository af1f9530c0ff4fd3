// Per-step remeshing (issue 5, part 1): a sphere moved through a fluid box step by step keeps its
// solid tets and interface identically, no tet inverts, the fluid stays above the dihedral
// threshold, and the complex stays conforming and fills the box.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>

#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/primitives.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesh_region.hpp"
#include "mesh/remesher.hpp"
#include "mesh/sliver_perturbation.hpp"
#include "mesh/structured_box.hpp"

using namespace tetfsi::mesh;

namespace {

TetMesh sphere_in_box() {
  MeshSizing sizing;
  sizing.edge_length = 0.12;  // uniform, the remeshing target below
  return build_complex({-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}, {make_sphere(0.25, 3)}, sizing);
}

/// Solid tets as sorted vertex 4-tuples, in the numbering given by `to_old` (identity if empty).
std::set<std::array<int, 4>> solid_tets(const TetMesh& m, const std::vector<int>& to_old = {}) {
  std::set<std::array<int, 4>> out;
  for (int t = 0; t < m.num_tets(); ++t) {
    if (m.subdomain[t] == kFluidSubdomain) continue;
    std::array<int, 4> k = m.tets[t];
    if (!to_old.empty())
      for (int& v : k) v = to_old[v];
    std::sort(k.begin(), k.end());
    out.insert(k);
  }
  return out;
}

double volume(const TetMesh& m, bool solid_only) {
  double v = 0.0;
  for (int t = 0; t < m.num_tets(); ++t)
    if (!solid_only || m.subdomain[t] != kFluidSubdomain) v += signed_volume(m, t);
  return v;
}

/// New positions: solid vertices translated by dx, the rest unchanged.
std::vector<Eigen::Vector3d> translated_solid(const TetMesh& m, const Eigen::Vector3d& dx) {
  std::vector<Eigen::Vector3d> p = m.vertices;
  std::vector<char> solid(m.vertices.size(), 0);
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.subdomain[t] != kFluidSubdomain)
      for (int v : m.tets[t]) solid[v] = 1;
  for (std::size_t v = 0; v < p.size(); ++v)
    if (solid[v]) p[v] += dx;
  return p;
}

/// Runs `steps` remesh steps moving the solid by dx each; returns the reports.
std::vector<RemeshReport> run_steps(RemeshOptions options, int steps, const Eigen::Vector3d& dx) {
  std::vector<RemeshReport> reports;
  TetMesh mesh = sphere_in_box();
  const double solid_volume = volume(mesh, true);
  for (int step = 0; step < steps; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const auto target = translated_solid(mesh, dx);
    const RemeshResult r = remesh_step(mesh, target, options);
    std::printf("step %d: %s\n", step, r.report.summary().c_str());
    EXPECT_TRUE(r.report.quality_ok);
    EXPECT_GE(r.report.min_dihedral_deg, options.min_dihedral_deg);
    const QualityReport q = quality_report(r.mesh);
    EXPECT_EQ(q.inverted + q.degenerate, 0);
    // Solid tets identical (same vertices, through old_index), solid vertices at their targets.
    EXPECT_EQ(solid_tets(r.mesh, r.old_index), solid_tets(mesh));
    int moved_solid_vertices = 0;
    for (int v = 0; v < r.mesh.num_vertices(); ++v) {
      if (r.old_index[v] >= 0 && target[r.old_index[v]] != mesh.vertices[r.old_index[v]]) {
        EXPECT_EQ(r.mesh.vertices[v], target[r.old_index[v]]);
        ++moved_solid_vertices;
      }
    }
    EXPECT_GT(moved_solid_vertices, 0);
    EXPECT_NEAR(volume(r.mesh, true), solid_volume, 1e-12);  // rigid motion
    EXPECT_NEAR(volume(r.mesh, false), 1.2 * 1.2 * 1.2, 1e-12);
    const InterfaceCheck check = check_interface(r.mesh);
    EXPECT_TRUE(check.conforming()) << check.first_defect;
    mesh = r.mesh;
    reports.push_back(r.report);
  }
  return reports;
}

}  // namespace

// Seen: full remesh, fluid min dihedral 17.9 and 21.7 deg after the two steps; band remesh 7.2 deg.
// A target edge length far from the mesh's own (remeshing a graded mesh to 0.1 m uniformly) gave
// 0.1 deg, hence the note on RemeshOptions::target_edge_length.
TEST(Remesher, SphereMovesThroughTheBox) {
  RemeshOptions options;
  options.target_edge_length = 0.12;
  run_steps(options, 2, {0.03, 0.0, 0.0});
}

TEST(Remesher, BandRemeshKeepsTheSameGuarantees) {
  RemeshOptions options;
  options.target_edge_length = 0.12;
  options.band = 0.15;
  for (const RemeshReport& r : run_steps(options, 2, {0.0, 0.03, 0.01})) {
    EXPECT_TRUE(r.local);  // CGAL got the band, a ring and the solid, not the whole mesh
    EXPECT_TRUE(r.remeshed);
  }
}

// Move, remesh when needed: a motion of 1% of the edge length leaves the mesh good (moved only,
// old_index the identity); 0.08 m steps spoil tets near the sphere, and the adaptive band then
// remeshes fewer fluid tets than the whole fluid.
TEST(Remesher, RemeshOnlyWhenNeeded) {
  RemeshOptions options;
  options.target_edge_length = 0.12;
  options.remesh_only_when_needed = true;
  const std::vector<RemeshReport> small = run_steps(options, 2, {0.0012, 0.0, 0.0});
  for (const RemeshReport& r : small) {
    EXPECT_FALSE(r.remeshed);
    EXPECT_EQ(r.passes, 0);
  }
  options.band = 0.15;
  options.adaptive_band = true;
  // The default stiffened motion keeps this mesh above 5 deg for these moves (no remesh needed);
  // the plain Laplacian (χ = 0) spoils it, which exercises the remesh-when-needed path.
  options.motion.stiffening_exponent = 0.0;
  const std::vector<RemeshReport> large = run_steps(options, 3, {0.08, 0.0, 0.0});
  int remeshed = 0;
  for (const RemeshReport& r : large) {
    if (!r.remeshed) continue;
    ++remeshed;
    EXPECT_LT(r.remeshed_fluid_tets, r.num_fluid_tets / 2);
  }
  EXPECT_GE(remeshed, 1);
}

// The sliver pass opens a sliver made by hand (an interior vertex of a 2x2x2 Kuhn box pushed
// almost onto a face of a tet) and moves no box-boundary vertex.
TEST(Remesher, SliverPassOpensASliver) {
  TetMesh m = structured_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2);
  const TetMesh original = m;
  int centre = -1;
  for (int v = 0; v < m.num_vertices(); ++v)
    if ((m.vertices[v] - Eigen::Vector3d(0.5, 0.5, 0.5)).norm() < 1e-12) centre = v;
  ASSERT_GE(centre, 0);
  // Push the centre toward a corner along the diagonal until the worst tet is below 5 deg.
  for (double s = 0.0; s < 0.5 && quality_report(m).min_dihedral_deg > 5.0; s += 0.01)
    m.vertices[centre] = Eigen::Vector3d::Constant(0.5 + s) + Eigen::Vector3d(0.0, 0.003, -0.003);
  const QualityReport before = quality_report(m);
  ASSERT_LT(before.min_dihedral_deg, 5.0);
  ASSERT_EQ(before.inverted + before.degenerate, 0);
  const SliverPassReport r = perturb_slivers(m, 10.0);
  const QualityReport after = quality_report(m);
  std::printf("sliver pass: min dihedral %.2f -> %.2f deg, slivers %d -> %d\n", before.min_dihedral_deg,
              after.min_dihedral_deg, r.slivers_before, r.slivers_after);
  EXPECT_GT(r.slivers_before, 0);
  EXPECT_EQ(r.slivers_after, 0);
  EXPECT_GE(after.min_dihedral_deg, 10.0);
  EXPECT_EQ(after.inverted + after.degenerate, 0);
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (v != centre) {
      EXPECT_EQ(m.vertices[v], original.vertices[v]);
    }
  }
}

// Deterministic: the same band remesh twice gives the same mesh, vertex for vertex.
TEST(Remesher, SameInputSameMesh) {
  const TetMesh mesh = sphere_in_box();
  RemeshOptions options;
  options.target_edge_length = 0.12;
  options.band = 0.15;
  const auto target = translated_solid(mesh, {0.02, 0.01, 0.0});
  const RemeshResult a = remesh_step(mesh, target, options), b = remesh_step(mesh, target, options);
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
  EXPECT_EQ(a.mesh.tets, b.mesh.tets);
  EXPECT_EQ(a.mesh.subdomain, b.mesh.subdomain);
  EXPECT_EQ(a.old_index, b.old_index);
}

TEST(Remesher, TooLargeAStepIsAnError) {
  const TetMesh mesh = sphere_in_box();
  RemeshOptions options;
  // 0.4 m moves the sphere (r = 0.25) through the box wall at 0.6: tets must invert.
  EXPECT_THROW(remesh_step(mesh, translated_solid(mesh, {0.4, 0, 0}), options), MeshError);
}

// resized_tets (remesh_region.hpp): on a 8 x 8 x 8 Kuhn box, a sizing field that moved from 0.125 m
// to 0.05 m for x < 0.25 m flags exactly the tets with a vertex there, and one ring adds the tets
// sharing a vertex with them; a field that did not move flags none, one 3x coarser flags all,
// one that moved by less than the ratio none.
TEST(RemeshRegion, ResizedTetsAreWhereTheFieldMoved) {
  const TetMesh box = structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 8, 8, 8);
  const auto uniform = [](double h) { return [h](const Eigen::Vector3d&) { return h; }; };
  const auto fine_strip = [](const Eigen::Vector3d& x) { return x.x() < 0.25 ? 0.05 : 0.125; };
  const std::vector<char> strip = resized_tets(box, uniform(0.125), fine_strip, 1.3, 0);
  const std::vector<char> grown = resized_tets(box, uniform(0.125), fine_strip, 1.3, 1);
  int added = 0;
  for (int t = 0; t < box.num_tets(); ++t) {
    double lowest = 1.0;
    for (int v : box.tets[t]) lowest = std::min(lowest, box.vertices[v].x());
    EXPECT_EQ(strip[t] != 0, lowest < 0.25) << "tet " << t;
    EXPECT_TRUE(!strip[t] || grown[t]);
    if (grown[t] && !strip[t]) {
      ++added;
      EXPECT_LE(lowest, 0.25 + 1e-12) << "tet " << t;  // shares a vertex with a flagged tet
    }
  }
  EXPECT_GT(added, 0);
  const auto count = [](const std::vector<char>& f) { return std::count(f.begin(), f.end(), 1); };
  EXPECT_EQ(count(resized_tets(box, fine_strip, fine_strip, 1.3, 2)), 0);
  EXPECT_EQ(count(resized_tets(box, uniform(0.125), uniform(0.375), 1.3, 0)), box.num_tets());
  EXPECT_EQ(count(resized_tets(box, uniform(0.125), uniform(0.15), 1.3, 0)), 0);
}

// RemeshOptions::remesh_tets: refining a slab x < 0.15 m of a 6 x 6 x 6 Kuhn box (mean edge 0.236 m)
// to 0.08 m remeshes only the tets resized_tets flags (a local remesh), keeps every tet away from them as it
// was (same vertices, through old_index), fills the box (volume 1 m^3 to round-off), and makes the
// slab fine while the far side stays coarse.
TEST(Remesher, RemeshTetsRefinesOnlyWhereTheFieldMoved) {
  const TetMesh box = structured_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 6, 6, 6);
  RemeshOptions options;
  options.target_edge_length = mean_edge_length(box, kFluidSubdomain);
  options.size_at = [](const Eigen::Vector3d& x) { return x.x() < 0.15 ? 0.08 : 1.0; };
  const double h = options.target_edge_length;
  options.remesh_tets = resized_tets(
      box, [h](const Eigen::Vector3d&) { return h; },
      [&](const Eigen::Vector3d& x) { return std::min(h, options.size_at(x)); }, 1.3, 1);
  const RemeshResult r = remesh_step(box, box.vertices, options);
  std::printf("%s\n", r.report.summary().c_str());
  EXPECT_TRUE(r.report.local);
  EXPECT_LT(r.report.remeshed_fluid_tets, box.num_tets() / 2);
  EXPECT_NEAR(volume(r.mesh, false), 1.0, 1e-12);
  const QualityReport q = quality_report(r.mesh);
  EXPECT_EQ(q.inverted + q.degenerate, 0);
  std::set<std::array<int, 4>> kept;  // output tets made of input vertices only, as input numbering
  for (const auto& tet : r.mesh.tets) {
    std::array<int, 4> k{};
    for (int i = 0; i < 4; ++i) k[i] = r.old_index[tet[i]];
    std::sort(k.begin(), k.end());
    if (k[0] >= 0) kept.insert(k);
  }
  // Mean edge length of the tets whose centroid's x is in [x0, x1].
  const auto mean_edge = [](const TetMesh& m, double x0, double x1) {
    double sum = 0;
    int count = 0;
    for (const auto& v : m.tets) {
      double length = 0, cx = 0;
      for (int a = 0; a < 4; ++a) {
        cx += m.vertices[v[a]].x() / 4;
        for (int b = a + 1; b < 4; ++b) length += (m.vertices[v[a]] - m.vertices[v[b]]).norm() / 6;
      }
      if (cx >= x0 && cx <= x1) sum += length, ++count;
    }
    return sum / count;
  };
  EXPECT_LT(mean_edge(r.mesh, 0, 0.1), 1.5 * 0.08);
  EXPECT_NEAR(mean_edge(r.mesh, 0.75, 1), mean_edge(box, 0.75, 1), 1e-12);
  for (int t = 0; t < box.num_tets(); ++t) {
    double lowest = 1.0;
    for (int v : box.tets[t]) lowest = std::min(lowest, box.vertices[v].x());
    if (lowest < 0.7) continue;
    std::array<int, 4> k = box.tets[t];
    std::sort(k.begin(), k.end());
    EXPECT_TRUE(kept.count(k)) << "tet " << t << " beyond x = 0.7 m was changed";
  }
}
