// Per-step remeshing (issue 5, part 1): a sphere moved through a fluid box step by step keeps its
// solid tets and interface identically, no tet inverts, the fluid stays above the dihedral
// threshold, and the complex stays conforming and fills the box.
#include <gtest/gtest.h>

#include <set>

#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/primitives.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesher.hpp"

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

void run_steps(RemeshOptions options, int steps, const Eigen::Vector3d& dx) {
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
  }
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
  run_steps(options, 2, {0.0, 0.03, 0.01});
}

TEST(Remesher, TooLargeAStepIsAnError) {
  const TetMesh mesh = sphere_in_box();
  RemeshOptions options;
  // 0.4 m moves the sphere (r = 0.25) through the box wall at 0.6: tets must invert.
  EXPECT_THROW(remesh_step(mesh, translated_solid(mesh, {0.4, 0, 0}), options), MeshError);
}
