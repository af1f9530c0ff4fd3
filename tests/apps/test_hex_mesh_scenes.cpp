// hex8 solids from hex mesh files and under any placement, through `tetfsi run`:
//  - patch test: an irregular hex mesh of a box (interior nodes jittered by up to 0.2 cells), written
//    as .vtu and as Gmsh .msh 4.1, placed with a general rotation and a translation, with the
//    linear field u = G X + c (|G| ~ 1e-4) prescribed on every boundary node (one world box per
//    node) in one static load step. A homogeneous deformation is the exact solution of the
//    nonlinear problem and lies in the trilinear hexes' span on any mesh, so every free node must
//    land on it: to 1e-10 of max |u| (Newton to a relative residual of 1e-13; round-off);
//  - placement: data/scenes/hex_rotated_cantilever.json (rotated 30 deg about x and y, clamped and
//    loaded through world boxes) against the same beam axis-aligned with the load rotated back:
//    R^T u_rotated = u_aligned at every node to 1e-10 of the tip deflection (the Total Lagrangian
//    hex is objective: only round-off and the Newton tolerance 1e-10 separate them). The tip
//    deflection of the default enhanced hexes is within 2% of Euler-Bernoulli + Timoshenko shear;
//    `formulation: "standard"` locks (solid/hex/README.md);
//  - the MacNeal & Harder (1985) 7-hex patch-test mesh, whose hex 3 has a negative corner Jacobian
//    but positive Jacobians at every Gauss point, read from a .vtu file: accepted, and u = G X + c
//    on its 8 cube corners gives G X + c at the 8 interior nodes to 1e-10, both formulations;
//  - a hex mesh from a Gmsh .msh file: data/scenes/hex_curved_cantilever.json, the quarter ring of
//    data/scenes/meshes/quarter_ring_hex.msh (remade here by scripts/make_quarter_ring_hex.py and
//    compared byte for byte), clamped at one end, loaded at the other: tip displacement against
//    Castigliano's bending-only values pi F R^3/(4EI) and F R^3/(2EI) within 0.5%. The reference
//    leaves out the axial and shear energy, about (1 + 2(1+nu)/kappa) h^2/(12 R^2) = 2.8e-3 of the
//    total at h/R = 0.1, and the fully integrated hexes lock by about 1e-3 at ds/dr = 0.1
//    (-1.9%, -0.47%, -0.11% in y at 80, 160, 320 cells along the arc).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "mesh/io/vtu_reader.hpp"
#include "mesh/surface_import.hpp"
#include "tests/hex/macneal_harder_mesh.hpp"
#include "tests/hex_mesh_files.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace tetfsi;

namespace {

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

/// Runs `tetfsi run scene --out out` in `dir`; returns the exit status.
int run(const fs::path& dir, const fs::path& scene, std::string* output) {
  int status = -1;
  *output = test::run_command("cd '" + dir.string() + "' && " + TETFSI_BINARY + " run '" + scene.string() +
                                  "' --out out --quiet --threads 1 2>&1",
                              &status);
  return status;
}

/// Reference points and displacement of frame `frame` of solid `name` in `dir`/out.
void read_frame(const fs::path& dir, const std::string& name, int frame, std::vector<Eigen::Vector3d>& X,
                std::vector<Eigen::Vector3d>& u) {
  char file[64];
  std::snprintf(file, sizeof file, "%s_%05d.vtu", name.c_str(), frame);
  const auto grid = mesh::io::read_vtu(dir / "out" / name / file);
  X = grid.points;
  u.clear();
  for (const auto& a : grid.point_data)
    if (a.name == "displacement")
      for (int i = 0; i < grid.num_points(); ++i) u.emplace_back(a.values[3 * i], a.values[3 * i + 1], a.values[3 * i + 2]);
  ASSERT_EQ(u.size(), X.size());
}

}  // namespace

TEST(HexMeshScenes, PatchTestOnAnIrregularHexMeshFromVtuAndMsh) {
  const Eigen::Vector3d lo(0, 0, 0), hi(0.4, 0.3, 0.2);
  const mesh::HexMesh m = test::jittered_block(lo, hi, 4, 3, 3, 0.2);
  test::TempDir dir("hex_patch");
  test::write_vtu_ascii(dir.path() / "block.vtu", m);
  test::write_msh_hexes(dir.path() / "block.msh", m, "4.1");
  const Eigen::Vector3d rotation(20, -35, 50), translation(0.1, 0.2, -0.3);
  const Eigen::Matrix3d R = mesh::placement_rotation(rotation);
  Eigen::Matrix3d G;  // a general small displacement gradient and a translation
  G << 1.0, -0.4, 0.3, 0.2, -0.7, 0.5, -0.6, 0.1, 0.8;
  G *= 1e-4;
  const Eigen::Vector3d c(2e-5, -1e-5, 3e-5);
  json bcs = json::array();
  int interior = 0;
  for (const auto& x : m.vertices) {
    const Eigen::Vector3d r = (x - lo).cwiseQuotient(hi - lo);
    if ((r.array() > 1e-9).all() && (r.array() < 1 - 1e-9).all()) {
      ++interior;
      continue;
    }
    const Eigen::Vector3d X = R * x + translation, d = Eigen::Vector3d::Constant(1e-6);
    bcs.push_back({{"type", "displacement"}, {"box", {{"lo", vec(X - d)}, {"hi", vec(X + d)}}},
                   {"value", vec(G * X + c)}});
  }
  ASSERT_EQ(interior, 3 * 2 * 2);
  for (const char* file : {"block.vtu", "block.msh"}) {
    SCOPED_TRACE(file);
    json s = {{"simulation", {{"end_time", 1.0}, {"dt", 1.0}, {"gravity", {0, 0, 0}}}},
              {"solids",
               {{{"name", "block"},
                 {"geometry", {{"type", "volume_mesh"}, {"file", file}}},
                 {"placement", {{"rotation_deg", vec(rotation)}, {"translation", vec(translation)}}},
                 {"model", {{"type", "hex8"}, {"analysis", "static"}}},
                 {"material", {{"density", 1000}, {"youngs_modulus", 1e6}, {"poissons_ratio", 0.3}}},
                 {"boundary_conditions", bcs},
                 {"static", {{"load_steps", 1}, {"residual_tolerance", 1e-13}, {"increment_tolerance", 1e-13}}}}}},
              {"export", {{"precision", "float64"}}}};  // the displacement as computed: checked to 1e-10
    std::ofstream(dir.path() / "patch.json") << s.dump(1);
    std::string out;
    ASSERT_EQ(run(dir.path(), dir.path() / "patch.json", &out), 0) << out;
    std::vector<Eigen::Vector3d> X, u;
    read_frame(dir.path(), "block", 1, X, u);
    ASSERT_EQ(X.size(), m.vertices.size());
    double err = 0, size = 0;
    for (std::size_t i = 0; i < X.size(); ++i) {
      EXPECT_LE((X[i] - (R * m.vertices[i] + translation)).norm(), 1e-14);  // the placed file, node for node
      err = std::max(err, (u[i] - (G * X[i] + c)).norm());
      size = std::max(size, u[i].norm());
    }
    EXPECT_LE(err, 1e-10 * size) << "max |u - (G X + c)| = " << err << " m, max |u| = " << size << " m";
    std::cout << file << ": patch test error " << err / size << " of max |u|\n";
  }
}

TEST(HexMeshScenes, RotatedCantileverDeflectsAsTheAxisAlignedOne) {
  test::TempDir dir("hex_rotated_cantilever");
  const fs::path shipped = fs::path(TETFSI_SOURCE_DIR) / "data/scenes/hex_rotated_cantilever.json";
  json rotated = json::parse(std::ifstream(shipped), nullptr, true, true);
  const auto& place = rotated["solids"][0]["placement"];
  const Eigen::Vector3d rotation(place["rotation_deg"][0], place["rotation_deg"][1], place["rotation_deg"][2]);
  const Eigen::Vector3d translation(place["translation"][0], place["translation"][1], place["translation"][2]);
  const Eigen::Matrix3d R = mesh::placement_rotation(rotation);
  ASSERT_GT(rotation.cwiseAbs().minCoeff() + rotation.cwiseAbs().maxCoeff(), 0);
  // The same beam axis-aligned at the origin: ends at x = -+0.5, the load rotated back.
  json aligned = rotated;
  auto& s = aligned["solids"][0];
  s["placement"] = {{"rotation_deg", {0, 0, 0}}, {"translation", {0, 0, 0}}};
  auto& bcs = s["boundary_conditions"];
  ASSERT_EQ(bcs.size(), 2u);
  bcs[0]["box"] = {{"lo", {-0.503, -0.053, -0.053}}, {"hi", {-0.497, 0.053, 0.053}}};
  bcs[1]["box"] = {{"lo", {0.497, -0.053, -0.053}}, {"hi", {0.503, 0.053, 0.053}}};
  const Eigen::Vector3d f(bcs[1]["value"][0], bcs[1]["value"][1], bcs[1]["value"][2]);
  bcs[1]["value"] = vec(R.transpose() * f);
  // Both read back as computed (export.precision "float64"): compared to 1e-10 of the deflection.
  aligned["export"]["precision"] = rotated["export"]["precision"] = "float64";
  std::ofstream(dir.path() / "aligned.json") << aligned.dump(1);
  std::ofstream(dir.path() / "rotated.json") << rotated.dump(1);
  std::string out;
  ASSERT_EQ(run(dir.path(), dir.path() / "rotated.json", &out), 0) << out;
  std::vector<Eigen::Vector3d> Xr, ur, Xa, ua;
  const int steps = rotated["solids"][0]["static"]["load_steps"];
  read_frame(dir.path(), "beam", steps, Xr, ur);
  fs::remove_all(dir.path() / "out");
  ASSERT_EQ(run(dir.path(), dir.path() / "aligned.json", &out), 0) << out;
  read_frame(dir.path(), "beam", steps, Xa, ua);
  ASSERT_EQ(Xr.size(), Xa.size());
  int tip = 0;
  double err = 0;
  for (std::size_t i = 0; i < Xa.size(); ++i) {
    ASSERT_LE((Xr[i] - (R * Xa[i] + translation)).norm(), 1e-14);  // node i is the same material point
    err = std::max(err, (R.transpose() * ur[i] - ua[i]).norm());
    if ((Xa[i] - Eigen::Vector3d(0.5, 0, 0)).norm() < (Xa[tip] - Eigen::Vector3d(0.5, 0, 0)).norm()) tip = static_cast<int>(i);
  }
  const double deflection = -ua[tip].y();
  EXPECT_LE(err, 1e-10 * deflection) << "max |R^T u_rotated - u_aligned| = " << err << " m";
  // Euler-Bernoulli with Timoshenko shear: F L^3 / (3 E I) + F L / (kappa G A), kappa = 5/6.
  const auto& mat = rotated["solids"][0]["material"];
  const double E = mat["youngs_modulus"], nu = mat["poissons_ratio"], L = 1.0, h = 0.1, F = 9 * 200.0;
  const double I = h * h * h * h / 12, shear = E / (2 * (1 + nu));
  const double reference = F * L * L * L / (3 * E * I) + F * L / (5.0 / 6.0 * shear * h * h);
  std::cout << "tip deflection " << deflection << " m, Euler-Bernoulli + shear " << reference << " m ("
            << (deflection / reference - 1) * 100 << "%), rotated vs aligned " << err / deflection << "\n";
  // The scene's hexes are enhanced by default (solid/hex/hex8_enhanced.hpp): within 2% of the
  // beam theory, as tests/hex/test_hex_bending.cpp with one hex through the thickness.
  EXPECT_NEAR(deflection / reference, 1.0, 0.02);
  // `model.formulation: "standard"` reaches the model: the fully integrated hex locks (stiffer by
  // about (G/E)(dx/h)^2 and more at cells 1.25 h long).
  s["model"]["formulation"] = "standard";
  std::ofstream(dir.path() / "standard.json") << aligned.dump(1);
  fs::remove_all(dir.path() / "out");
  ASSERT_EQ(run(dir.path(), dir.path() / "standard.json", &out), 0) << out;
  std::vector<Eigen::Vector3d> Xs, us;
  read_frame(dir.path(), "beam", steps, Xs, us);
  std::cout << "standard hex8: tip deflection " << -us[tip].y() << " m (" << (-us[tip].y() / reference - 1) * 100
            << "%)\n";
  EXPECT_LT(-us[tip].y(), 0.95 * reference);
}

TEST(HexMeshScenes, CurvedCantileverFromAGmshFileMatchesCastigliano) {
  const fs::path scenes = fs::path(TETFSI_SOURCE_DIR) / "data/scenes";
  test::TempDir dir("hex_curved_cantilever");
  int status = -1;
  const std::string made = test::run_command(std::string(TETFSI_PYTHON) + " '" + TETFSI_SOURCE_DIR +
                                                 "/scripts/make_quarter_ring_hex.py' '" +
                                                 (dir.path() / "ring.msh").string() + "' 2>&1",
                                             &status);
  ASSERT_EQ(status, 0) << made;
  auto text = [](const fs::path& f) {
    std::ifstream in(f);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(text(dir.path() / "ring.msh"), text(scenes / "meshes/quarter_ring_hex.msh"))
      << "data/scenes/meshes/quarter_ring_hex.msh is not what scripts/make_quarter_ring_hex.py makes";
  std::string out;
  ASSERT_EQ(run(dir.path(), scenes / "hex_curved_cantilever.json", &out), 0) << out;
  std::vector<Eigen::Vector3d> X, u;
  read_frame(dir.path(), "ring", 1, X, u);
  const Eigen::Vector3d tip(0, 1, -0.05);
  int k = 0;
  for (std::size_t i = 0; i < X.size(); ++i)
    if ((X[i] - tip).norm() < (X[k] - tip).norm()) k = static_cast<int>(i);
  ASSERT_LT((X[k] - tip).norm(), 1e-12);
  const double E = 1e7, h = 0.1, b = 0.1, R = 1.0, F = 6 * 0.02, I = b * h * h * h / 12;
  const double dy = M_PI * F * R * R * R / (4 * E * I), dx = F * R * R * R / (2 * E * I);
  std::cout << "tip (" << u[k].x() << ", " << u[k].y() << ") m, Castigliano (" << dx << ", " << dy << ") m: "
            << (u[k].x() / dx - 1) * 100 << "%, " << (u[k].y() / dy - 1) * 100 << "%\n";
  EXPECT_NEAR(u[k].x() / dx, 1.0, 5e-3);
  EXPECT_NEAR(u[k].y() / dy, 1.0, 5e-3);
}

TEST(HexMeshScenes, MacNealHarderMeshFromVtuPassesThePatchTest) {
  const mesh::HexMesh m = test::macneal_harder_mesh();
  test::TempDir dir("hex_macneal_harder");
  test::write_vtu_ascii(dir.path() / "mh.vtu", m);
  Eigen::Matrix3d G;
  G << 1.0, -0.4, 0.3, 0.2, -0.7, 0.5, -0.6, 0.1, 0.8;
  G *= 1e-3;
  const Eigen::Vector3d c(2e-4, -1e-4, 3e-4);
  json bcs = json::array();
  for (int v = 0; v < 8; ++v) {
    const Eigen::Vector3d X = m.vertices[v], d = Eigen::Vector3d::Constant(1e-6);
    bcs.push_back({{"type", "displacement"}, {"box", {{"lo", vec(X - d)}, {"hi", vec(X + d)}}}, {"value", vec(G * X + c)}});
  }
  for (const char* formulation : {"enhanced", "standard"}) {
    SCOPED_TRACE(formulation);
    json s = {{"simulation", {{"end_time", 1.0}, {"dt", 1.0}, {"gravity", {0, 0, 0}}}},
              {"solids",
               {{{"name", "cube"},
                 {"geometry", {{"type", "volume_mesh"}, {"file", "mh.vtu"}}},
                 {"model", {{"type", "hex8"}, {"analysis", "static"}, {"formulation", formulation}}},
                 {"material", {{"density", 1000}, {"youngs_modulus", 1e6}, {"poissons_ratio", 0.3}}},
                 {"boundary_conditions", bcs},
                 {"static", {{"load_steps", 1}, {"residual_tolerance", 1e-13}, {"increment_tolerance", 1e-13}}}}}},
              {"export", {{"precision", "float64"}}}};
    std::ofstream(dir.path() / "mh.json") << s.dump(1);
    std::string out;
    fs::remove_all(dir.path() / "out");
    ASSERT_EQ(run(dir.path(), dir.path() / "mh.json", &out), 0) << out;
    std::vector<Eigen::Vector3d> X, u;
    read_frame(dir.path(), "cube", 1, X, u);
    ASSERT_EQ(X.size(), 16u);
    double err = 0, size = 0;
    for (std::size_t i = 0; i < X.size(); ++i) {
      err = std::max(err, (u[i] - (G * X[i] + c)).norm());
      size = std::max(size, u[i].norm());
    }
    EXPECT_LE(err, 1e-10 * size) << "max |u - (G X + c)| = " << err << " m";
    std::cout << "MacNeal-Harder, " << formulation << ": patch test error " << err / size << " of max |u|\n";
  }
}
