// Solids whose FEM mesh is read from a file (geometry "volume_mesh", run::volume_mesh_of):
//  - patch test: an irregular CGAL tet mesh of a box, written as .vtu and as .msh (4.1, 2.2) and
//    read back through the scene's reader, reproduces a linear displacement field u = G x + c
//    prescribed on its boundary nodes: the free (interior) nodes solve K0 u = 0 and must land on
//    the linear field to 1e-10 of its size (constant-strain tets pass the patch test exactly; the
//    bound is round-off);
//  - objectivity of the placement: a cantilever read from one .msh file axis-aligned and rotated
//    by 30 deg about x and 30 deg about y (gravity and the clamp rotated with it) gives, after
//    the same 30 StVK Newmark steps, the same tip displacement rotated back, to 1e-8 relative.
#include <gtest/gtest.h>

#include <cmath>

#include "apps/run/solid_geometry.hpp"
#include "apps/run/tet_tools.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/io/msh_writer.hpp"
#include "mesh/io/vtu_writer.hpp"
#include "mesh/primitives.hpp"
#include "mesh/surface_import.hpp"
#include "solid/analysis/linear_analysis.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/tet/tet_model.hpp"
#include "tests/test_support.hpp"
#include "tests/volume_mesh_files.hpp"

namespace fs = std::filesystem;
using namespace tetfsi;

namespace {

mesh::TetMesh generated_box(const Eigen::Vector3d& size, double edge, const Eigen::Vector3d& shift) {
  mesh::MeshSizing sizing;
  sizing.edge_length = edge;
  mesh::TetMesh m = mesh::mesh_solid(mesh::make_box(size), sizing);
  for (auto& v : m.vertices) v += shift;
  return m;
}

/// The resolved /solids/i JSON of a volume_mesh solid.
scene::Json volume_solid(const fs::path& file, const Eigen::Vector3d& rotation_deg, const Eigen::Vector3d& translation) {
  scene::Json s;
  s["name"] = "body";
  s["geometry"] = {{"type", "volume_mesh"}, {"file", file.string()}, {"unit_scale", 1.0}};
  s["placement"] = {{"rotation_deg", {rotation_deg.x(), rotation_deg.y(), rotation_deg.z()}},
                    {"translation", {translation.x(), translation.y(), translation.z()}}};
  return s;
}

}  // namespace

TEST(VolumeMeshSolid, PatchTestOnAnIrregularMeshReadFromVtuAndMsh) {
  const mesh::TetMesh generated = generated_box({0.4, 0.2, 0.2}, 0.06, Eigen::Vector3d::Zero());
  test::TempDir dir("patch");
  mesh::io::write_vtu(dir.path() / "box.vtu", mesh::io::make_grid(generated));
  test::write_vtu_ascii(dir.path() / "box_ascii.vtu", generated);
  mesh::io::write_msh(dir.path() / "box41.msh", generated, mesh::io::MshVersion::k41);
  mesh::io::write_msh(dir.path() / "box22.msh", generated, mesh::io::MshVersion::k22);
  Eigen::Matrix3d G;  // a general small displacement gradient (strain ~1e-4) and a translation
  G << 1.0, -0.4, 0.3, 0.2, -0.7, 0.5, -0.6, 0.1, 0.8;
  G *= 1e-4;
  const Eigen::Vector3d c(2e-5, -1e-5, 3e-5);
  for (const char* name : {"box.vtu", "box_ascii.vtu", "box41.msh", "box22.msh"}) {
    std::vector<std::string> warnings;
    const mesh::TetMesh tets = run::volume_mesh_of(volume_solid(dir.path() / name, {0, 0, 0}, {0, 0, 0}), warnings);
    ASSERT_EQ(tets.num_tets(), generated.num_tets()) << name;
    solid::TetMaterial material;
    material.youngs_modulus = 1e6;
    material.poisson_ratio = 0.3;
    const solid::TetModel model(tets, material);
    std::vector<int> boundary;
    run::boundary_surface(tets, &boundary);
    std::vector<char> fixed(3 * model.num_nodes(), 0);
    for (int n : boundary) fixed[3 * n] = fixed[3 * n + 1] = fixed[3 * n + 2] = 1;
    const int interior = model.num_nodes() - static_cast<int>(boundary.size());
    ASSERT_GT(interior, 10) << name;
    Eigen::VectorXd u_lin(3 * model.num_nodes());
    for (int n = 0; n < model.num_nodes(); ++n) u_lin.segment<3>(3 * n) = G * tets.vertices[n] + c;
    Eigen::VectorXd force;
    solid::SparseMatrix K;
    ASSERT_TRUE(model.evaluate(Eigen::VectorXd::Zero(u_lin.size()), force, &K));
    // u = u_lin + w, w = 0 on the boundary: K0 w = -K0 u_lin on the free DOFs.
    const Eigen::VectorXd w = solid::solve_linear_static(model, fixed, -(K * u_lin));
    const double error = w.cwiseAbs().maxCoeff() / u_lin.cwiseAbs().maxCoeff();
    EXPECT_LT(error, 1e-10) << name << ": " << interior << " interior nodes";
    std::printf("[ patch ] %s: %d tets, %d interior nodes, max |u - (G x + c)| / max |G x + c| = %.3g\n", name,
                tets.num_tets(), interior, error);
  }
}

TEST(VolumeMeshSolid, RotatedCantileverGivesTheAxisAlignedDeflection) {
  // Beam 1 x 0.1 x 0.1 m along x from x = 0 (clamped) to x = 1 (tip).
  const mesh::TetMesh generated = generated_box({1.0, 0.1, 0.1}, 0.05, {0.5, 0, 0});
  test::TempDir dir("rotated_cantilever");
  mesh::io::write_msh(dir.path() / "beam.msh", generated);
  const Eigen::Vector3d rotation(30, 30, 0), translation(0.2, -0.1, 0.3);
  const Eigen::Matrix3d R = mesh::placement_rotation(rotation);
  std::vector<std::string> warnings;
  const mesh::TetMesh straight = run::volume_mesh_of(volume_solid(dir.path() / "beam.msh", {0, 0, 0}, {0, 0, 0}), warnings);
  const mesh::TetMesh turned = run::volume_mesh_of(volume_solid(dir.path() / "beam.msh", rotation, translation), warnings);
  ASSERT_EQ(straight.num_vertices(), turned.num_vertices());
  std::vector<int> clamped;
  int tip = 0;
  for (int n = 0; n < straight.num_vertices(); ++n) {
    if (straight.vertices[n].x() < 1e-9) clamped.push_back(n);
    if ((straight.vertices[n] - Eigen::Vector3d(1, 0, 0)).norm() < (straight.vertices[tip] - Eigen::Vector3d(1, 0, 0)).norm())
      tip = n;
    ASSERT_LT((turned.vertices[n] - (R * straight.vertices[n] + translation)).norm(), 1e-14);
  }
  ASSERT_GT(clamped.size(), 4u);
  solid::TetMaterial material;
  material.youngs_modulus = 1e8;
  material.poisson_ratio = 0.3;
  material.density = 1000;
  auto deflection = [&](const mesh::TetMesh& tets, const Eigen::Vector3d& gravity) {
    const solid::TetModel model(tets, material);
    solid::NewmarkSettings settings;
    const double time_step = 0.01;
    settings.rayleigh_alpha = 60;
    settings.gravity = gravity;
    solid::NewmarkIntegrator integrator(model, settings);
    integrator.fix_nodes(clamped);
    for (int k = 0; k < 30; ++k) integrator.step(time_step);
    return Eigen::VectorXd(integrator.displacement());
  };
  const Eigen::Vector3d g(0, -9.81, 0);
  const Eigen::VectorXd d0 = deflection(straight, g), d1 = deflection(turned, R * g);
  const Eigen::Vector3d tip0 = d0.segment<3>(3 * tip), tip1 = R.transpose() * d1.segment<3>(3 * tip);
  EXPECT_GT(-tip0.y(), 5e-3);  // it sags (Euler-Bernoulli static: 14.7 mm; constant-strain tets are stiffer)
  EXPECT_LT((tip1 - tip0).norm(), 1e-8 * tip0.norm()) << "axis-aligned " << tip0.transpose() << ", rotated back "
                                                        << tip1.transpose();
  std::printf("[ rotated ] tip sag %.6g m, |R^T d_rot - d| / |d| = %.3g\n", -tip0.y(), (tip1 - tip0).norm() / tip0.norm());
}
