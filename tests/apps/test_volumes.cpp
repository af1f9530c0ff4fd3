// export.volumes "vdb" through `tetfsi run`, read back with OpenVDB's own reader (openvdb::io::File):
//  - smoke_plume (fluid runner, 0.2 s): volumes/fluid_NNNNN.vdb holds `density` (fog volume),
//    `temperature` and `velocity` (Vec3f) at export.voxel_size; at random voxels the values equal
//    the frame's .vtu point fields interpolated linearly in the tet holding the voxel centre (read
//    with the project's VTU reader, located with the fluid's PointLocator), to float precision, and a
//    voxel is active exactly when its centre lies in the fluid (not in the sphere, not outside the box);
//  - the same run with export.up_axis "z" holds voxel (i, -k, j) with the turned velocity for
//    voxel (i, j, k) of the Y-up run, a second Y-up run writes the same bytes (deterministic), and
//    a shorter run into its folder leaves none of its later .vdb frames;
//  - dam_break_ci (coupled, a free surface, 0.1 s): the level-set grid `surface` (GRID_LEVEL_SET,
//    background 3 voxels) is zero within one voxel at every vertex of the frame's liquid surface PLY,
//    its sign is the .vtu level set's at random fluid points farther than 2 voxels from the surface,
//    and within the band it is the .vtu level set to one voxel + one mean edge; its velocity voxels
//    hold the .vtu velocity on the fluid nodes as the coupled runner moved them;
//  - a voxel size that would need too many voxels is refused by validate and run (exit 2, naming
//    /export/voxel_size).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include "fluid/advection/point_locator.hpp"
#include "fluid/operators/fluid_mesh.hpp"
#include "mesh/io/vtu_reader.hpp"
#include "ply_reader.hpp"
#include "cli_helpers.hpp"
#include "vtu_tets.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

/// Writes `scene` into `dir` and runs it into dir/out; returns the output folder.
fs::path run_scene(const json& scene, const fs::path& dir, const std::string& name) {
  const fs::path file = dir / (name + ".json");
  std::ofstream(file) << scene.dump(2);
  int status = -1;
  const std::string log = tetfsi_cmd("run " + file.string() + " --out " + (dir / name).string(), &status);
  EXPECT_EQ(status, 0) << log;
  return dir / name;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A frame's fluid .vtu as a fluid mesh with its point fields (in fluid-node order).
struct VtuFrame {
  tetfsi::fluid::FluidMesh mesh;
  std::map<std::string, std::vector<double>> point;  ///< name -> values (components interleaved)
  double mean_edge = 0;
};

VtuFrame read_frame(const fs::path& vtu) {
  const auto g = tetfsi::mesh::io::read_vtu(vtu);
  VtuFrame f;
  f.mesh = tetfsi::fluid::build_fluid_mesh(tet_mesh(g));
  f.mean_edge = f.mesh.mean_edge_length();
  for (const auto& a : g.point_data) {
    auto& v = f.point[a.name];
    v.resize(a.values.size());
    for (int n = 0; n < f.mesh.num_nodes(); ++n)
      for (int c = 0; c < a.components; ++c)
        v[a.components * n + c] = a.values[a.components * f.mesh.node_to_mesh_vertex[n] + c];
  }
  return f;
}

/// Component c of the P1 interpolant of point field `name` (of `components`) at location l.
double interpolate(const VtuFrame& f, const tetfsi::fluid::Location& l, const std::string& name, int components, int c) {
  const auto& v = f.point.at(name);
  double s = 0;
  for (int k = 0; k < 4; ++k) s += l.bary[k] * v[components * f.mesh.tets[l.tet][k] + c];
  return s;
}

template <class GridT>
typename GridT::Ptr grid(openvdb::io::File& file, const std::string& name) {
  EXPECT_TRUE(file.hasGrid(name)) << name;
  if (!file.hasGrid(name)) return nullptr;
  auto g = openvdb::gridPtrCast<GridT>(file.readGrid(name));
  EXPECT_TRUE(g) << name << " has another value type";
  return g;
}

class Volumes : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { openvdb::initialize(); }
};

json smoke_scene(const std::string& up_axis) {
  json s = committed("smoke_plume.json");
  s["simulation"]["end_time"] = 0.2;
  s["probes"] = json::array();
  s["export"] = {{"surfaces", "none"}, {"volumes", "vdb"}, {"voxel_size", 0.025}, {"up_axis", up_axis}};
  return s;
}

TEST_F(Volumes, SmokeGridsHoldTheFluidFieldsAtTheVoxelCentres) {
  TempDir dir("volumes_smoke");
  const fs::path out = run_scene(smoke_scene("y"), dir.path(), "y");
  const double h = 0.025;
  const VtuFrame frame = read_frame(out / "fluid" / "fluid_00002.vtu");
  tetfsi::fluid::PointLocator locator(frame.mesh);

  openvdb::io::File file((out / "volumes" / "fluid_00002.vdb").string());
  ASSERT_NO_THROW(file.open());
  auto density = grid<openvdb::FloatGrid>(file, "density");
  auto temperature = grid<openvdb::FloatGrid>(file, "temperature");
  auto velocity = grid<openvdb::Vec3fGrid>(file, "velocity");
  ASSERT_TRUE(density && temperature && velocity);
  EXPECT_FALSE(file.hasGrid("surface"));  // smoke: no liquid surface
  EXPECT_EQ(density->getGridClass(), openvdb::GRID_FOG_VOLUME);
  for (const openvdb::GridBase* g : {static_cast<openvdb::GridBase*>(density.get()),
                                     static_cast<openvdb::GridBase*>(temperature.get()),
                                     static_cast<openvdb::GridBase*>(velocity.get())}) {
    EXPECT_TRUE(g->transform().isLinear()) << g->getName();
    EXPECT_TRUE(g->transform().hasUniformScale()) << g->getName();
    EXPECT_NEAR(g->voxelSize()[0], h, 1e-12) << g->getName();
  }
  EXPECT_TRUE(velocity->isInWorldSpace());
  EXPECT_EQ(velocity->getVectorType(), openvdb::VEC_CONTRAVARIANT_RELATIVE);

  // Random voxels over the domain box [-0.4, 0.4] x [0, 1.2] x [-0.4, 0.4] and one layer around it.
  std::mt19937 rng(20);
  std::uniform_int_distribution<int> ix(-17, 17), iy(-1, 49), iz(-17, 17);
  auto d = density->getConstAccessor();
  auto t = temperature->getConstAccessor();
  auto u = velocity->getConstAccessor();
  int inside = 0, outside = 0, smoky = 0, hot = 0;
  double worst = 0;
  for (int n = 0; n < 3000; ++n) {
    const openvdb::Coord c(ix(rng), iy(rng), iz(rng));
    const Eigen::Vector3d x = Eigen::Vector3d(c.x(), c.y(), c.z()) * h;
    const auto l = locator.locate(x, -1);
    ASSERT_EQ(d.isValueOn(c), l.inside) << "voxel " << c << " at " << x.transpose();
    ASSERT_EQ(t.isValueOn(c), l.inside) << "voxel " << c;
    ASSERT_EQ(u.isValueOn(c), l.inside) << "voxel " << c;
    if (!l.inside) {
      ++outside;
      EXPECT_EQ(d.getValue(c), 0.0f);
      EXPECT_EQ(t.getValue(c), 0.0f);
      continue;
    }
    ++inside;
    const double smoke = interpolate(frame, l, "smoke", 1, 0), temp = interpolate(frame, l, "temperature", 1, 0);
    smoky += smoke > 0.01;
    hot += temp > 293.2;
    worst = std::max({worst, std::fabs(d.getValue(c) - smoke), std::fabs(t.getValue(c) - temp) / 373.15});
    EXPECT_NEAR(d.getValue(c), smoke, 1e-6) << "density at voxel " << c;
    EXPECT_NEAR(t.getValue(c), temp, 373.15 * 1e-6) << "temperature at voxel " << c;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(u.getValue(c)[k], interpolate(frame, l, "velocity", 3, k), 1e-6) << "velocity at voxel " << c;
  }
  // The sample covers smoke, heat and the sphere/outside (a test that sees only zeros proves nothing).
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 20);
  EXPECT_GT(smoky, 20);
  EXPECT_GT(hot, 20);
  std::printf("smoke_plume frame 2: %d voxels inside, %d outside; largest difference %.3g (relative)\n", inside,
              outside, worst);
  std::printf("bytes: %ju per frame (.vdb, frame 2), %ju (.vtu)\n",
              std::uintmax_t(fs::file_size(out / "volumes" / "fluid_00002.vdb")),
              std::uintmax_t(fs::file_size(out / "fluid" / "fluid_00002.vtu")));
}

TEST_F(Volumes, ZUpTurnsVoxelsAndVectorsAndRunsRepeatBitForBit) {
  TempDir dir("volumes_up");
  const fs::path y = run_scene(smoke_scene("y"), dir.path(), "y");
  const fs::path again = run_scene(smoke_scene("y"), dir.path(), "again");
  const fs::path z = run_scene(smoke_scene("z"), dir.path(), "z");
  for (int f = 0; f <= 2; ++f) {
    const std::string name = "volumes/fluid_0000" + std::to_string(f) + ".vdb";
    EXPECT_EQ(read_bytes(y / name), read_bytes(again / name)) << name << " differs between two runs";
  }
  json shorter = smoke_scene("y");
  shorter["simulation"]["end_time"] = 0.1;
  run_scene(shorter, dir.path(), "again");  // into the folder of an earlier, longer run
  EXPECT_TRUE(fs::exists(again / "volumes" / "fluid_00001.vdb"));
  EXPECT_FALSE(fs::exists(again / "volumes" / "fluid_00002.vdb")) << "the earlier run's frame is left";
  openvdb::io::File fy((y / "volumes" / "fluid_00002.vdb").string()), fz((z / "volumes" / "fluid_00002.vdb").string());
  fy.open();
  fz.open();
  auto dy = grid<openvdb::FloatGrid>(fy, "density"), dz = grid<openvdb::FloatGrid>(fz, "density");
  auto uy = grid<openvdb::Vec3fGrid>(fy, "velocity"), uz = grid<openvdb::Vec3fGrid>(fz, "velocity");
  ASSERT_TRUE(dy && dz && uy && uz);
  EXPECT_EQ(dy->activeVoxelCount(), dz->activeVoxelCount());
  auto az = dz->getConstAccessor();
  auto bz = uz->getConstAccessor();
  std::size_t checked = 0;
  for (auto it = uy->cbeginValueOn(); it; ++it) {
    openvdb::CoordBBox box;
    it.getBoundingBox(box);  // a voxel, or a pruned tile of equal values
    for (auto c = box.begin(); c; ++c) {
      const openvdb::Coord turned((*c).x(), -(*c).z(), (*c).y());
      const openvdb::Vec3f v = *it, w = bz.getValue(turned);
      ASSERT_TRUE(bz.isValueOn(turned)) << *c;
      ASSERT_EQ(w, openvdb::Vec3f(v.x(), -v.z(), v.y())) << *c;
      ASSERT_EQ(az.getValue(turned), dy->tree().getValue(*c)) << *c;
      ++checked;
    }
  }
  EXPECT_EQ(checked, uy->activeVoxelCount());
}

TEST_F(Volumes, LiquidSurfaceLevelSetMatchesTheSurfaceAndTheLevelSet) {
  TempDir dir("volumes_liquid");
  json s = committed("dam_break_ci.json");
  s["simulation"]["end_time"] = 0.1;
  s["probes"] = json::array();
  const double h = 0.02;
  s["export"] = {{"surfaces", "ply"}, {"volumes", "vdb"}, {"voxel_size", h}};
  const fs::path out = run_scene(s, dir.path(), "dam");
  const VtuFrame frame = read_frame(out / "fluid" / "fluid_00002.vtu");
  const PlyData ply = read_ply(out / "surfaces" / "liquid_00002.ply");
  ASSERT_GT(ply.positions.size(), 100u);

  openvdb::io::File file((out / "volumes" / "fluid_00002.vdb").string());
  ASSERT_NO_THROW(file.open());
  for (const char* name : {"density", "temperature", "velocity"}) EXPECT_TRUE(file.hasGrid(name)) << name;
  auto surface = grid<openvdb::FloatGrid>(file, "surface");
  ASSERT_TRUE(surface);
  EXPECT_EQ(surface->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_NEAR(surface->voxelSize()[0], h, 1e-12);
  EXPECT_NEAR(surface->background(), 3 * h, 1e-6);
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi(*surface);
  auto at = [&](const Eigen::Vector3d& x) { return double(phi.wsSample(openvdb::Vec3d(x.x(), x.y(), x.z()))); };

  double on_surface = 0;
  for (const auto& x : ply.positions) on_surface = std::max(on_surface, std::fabs(at(x)));
  EXPECT_LT(on_surface, h) << "the level set's zero lies farther than a voxel from a surface vertex";

  tetfsi::fluid::PointLocator locator(frame.mesh);
  std::mt19937 rng(20);
  std::uniform_real_distribution<double> ux(0, 1.6), uy(0, 0.8), uz(0, 0.4);
  int far = 0, near = 0, wrong_sign = 0;
  double band_error = 0;
  for (int n = 0; n < 4000; ++n) {
    const Eigen::Vector3d x(ux(rng), uy(rng), uz(rng));
    const auto l = locator.locate(x, -1);
    if (!l.inside) continue;
    const double ref = interpolate(frame, l, "level_set", 1, 0), v = at(x);
    if (std::fabs(ref) > 2 * h) {
      ++far;
      wrong_sign += (ref < 0) != (v < 0);
    } else {
      ++near;
      band_error = std::max(band_error, std::fabs(v - ref));
    }
  }
  // The coupled runner draws the frame on the fluid nodes moved with the solids (the .vtu points):
  // the velocity voxels hold the field on that mesh too.
  auto velocity = grid<openvdb::Vec3fGrid>(file, "velocity");
  ASSERT_TRUE(velocity);
  auto u = velocity->getConstAccessor();
  std::uniform_int_distribution<int> ix(-1, 81), iy(-1, 41), iz(-1, 21);
  int moving = 0;
  for (int n = 0; n < 2000; ++n) {
    const openvdb::Coord c(ix(rng), iy(rng), iz(rng));
    const auto l = locator.locate(Eigen::Vector3d(c.x(), c.y(), c.z()) * h, -1);
    ASSERT_EQ(u.isValueOn(c), l.inside) << "voxel " << c;
    if (!l.inside) continue;
    moving += u.getValue(c).length() > 0.1f;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(u.getValue(c)[k], interpolate(frame, l, "velocity", 3, k), 1e-5) << "velocity at voxel " << c;
  }
  EXPECT_GT(moving, 100);
  EXPECT_GT(far, 1000);
  EXPECT_GT(near, 50);
  EXPECT_EQ(wrong_sign, 0);
  EXPECT_LT(band_error, h + frame.mean_edge);
  std::printf("dam_break_ci frame 2: |phi| at %zu surface vertices <= %.3g m (voxel %.3g m); band error %.3g m "
              "(voxel + mean edge %.3g m) at %d points; sign checked at %d\n",
              ply.positions.size(), on_surface, h, band_error, h + frame.mean_edge, near, far);
}

TEST_F(Volumes, TooManyVoxelsIsRefusedNamingTheKey) {
  TempDir dir("volumes_bad");
  json s = smoke_scene("y");
  s["export"]["voxel_size"] = 1e-5;
  const fs::path file = dir.path() / "fine.json";
  std::ofstream(file) << s.dump(2);
  for (const std::string& cmd : {"validate " + file.string(), "run " + file.string() + " --out " + (dir.path() / "o").string()}) {
    int status = -1;
    const std::string log = tetfsi_cmd(cmd, &status);
    EXPECT_EQ(status, 2) << cmd << "\n" << log;
    EXPECT_NE(log.find("/export/voxel_size"), std::string::npos) << log;
  }
  s["export"]["voxel_size"] = 0;
  std::ofstream(file) << s.dump(2);
  int status = -1;
  const std::string log = tetfsi_cmd("validate " + file.string(), &status);
  EXPECT_EQ(status, 2) << log;
  EXPECT_NE(log.find("/export/voxel_size"), std::string::npos) << log;
}

}  // namespace
