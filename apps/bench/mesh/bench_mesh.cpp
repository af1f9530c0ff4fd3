/// @file bench_mesh.cpp
/// Benchmark of the CGAL Mesh_3 complex (issue 2) and of the per-step remesh (issue 5): the
/// Stanford bunny (not shipped: the path given, or bunny.obj in the data folder of
/// TETFSI_SHARED_DIR) in a fluid box at about 25k and 100k tets, and a sphere in a box. Error: volume of the meshed solid against
/// the volume enclosed by the input surface (and, for the sphere, against 4/3 pi r^3). Each case
/// runs in its own process (fork) so that the peak memory column is that case's own.
///
/// Usage: bench_mesh [bunny.obj | --remesh-only [name filter]]   (--remesh-only: the remesh-step cases
/// alone, or those whose name contains the filter, e.g. "~100k")
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <ctime>
#include <cstdio>
#include <functional>
#include <string>

#include "apps/bench/bench_support.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/primitives.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesher.hpp"
#include "mesh/surface_checks.hpp"
#include "mesh/surface_import.hpp"

using namespace tetfsi::mesh;
namespace bench = tetfsi::bench;

namespace {

double solid_volume(const TetMesh& m) {
  double v = 0.0;
  for (int t = 0; t < m.num_tets(); ++t)
    if (m.subdomain[t] != kFluidSubdomain) v += signed_volume(m, t);
  return v;
}

/// Meshes `solid` in `box`, prints one table row. `reference` is the exact solid volume.
void run_case(const std::string& name, const SurfaceMesh& solid, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
              const MeshSizing& sizing, double reference, const std::string& reference_name) {
  bench::Stopwatch clock;
  const std::clock_t cpu_start = std::clock();
  const TetMesh m = build_complex(lo, hi, {solid}, sizing);
  const double seconds = clock.seconds();
  const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const QualityReport q = quality_report(m);
  const InterfaceCheck check = check_interface(m);
  const double error = solid_volume(m) / reference - 1.0;
  char err[300], res[120];
  std::snprintf(err, sizeof err,
                "%+.2e rel. (solid volume vs %s); min dihedral %.1f deg, max %.1f; %d inverted; %s; cpu %.2f s",
                error, reference_name.c_str(), q.min_dihedral_deg, q.max_dihedral_deg, q.inverted,
                check.conforming() ? "interface conforming" : "INTERFACE NOT CONFORMING", cpu_seconds);
  std::snprintf(res, sizeof res, "%d tets (%d solid), h = %.4g m", q.num_tets,
                q.num_tets - q.tets_per_subdomain.at(kFluidSubdomain), sizing.edge_length);
  bench::print_row(name, res, err, seconds);
}

void in_child(const std::function<void()>& f) {
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid == 0) {
    try {
      f();
    } catch (const std::exception& e) {
      std::printf("error: %s\n", e.what());
      _exit(1);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
}

/// Complex (Mesh_3) cases: the bunny at ~25k and ~100k tets, graded, and a sphere.
void complex_cases(const SurfaceMesh& bunny, const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi,
                   double size, double v_bunny) {
  // Uniform size h; the tet count scales as h^-3 (h chosen for ~25k and ~100k tets).
  for (const auto& [label, h] : {std::pair{"bunny in box, ~25k tets", 0.081 * size},
                                 std::pair{"bunny in box, ~100k tets", 0.0503 * size}}) {
    MeshSizing sizing;
    sizing.edge_length = h;
    in_child([&] { run_case(label, bunny, box_lo, box_hi, sizing, v_bunny, "input surface"); });
  }
  // Graded: fine at the bunny, coarse far away.
  {
    MeshSizing sizing;
    sizing.edge_length = 0.08 * size;
    sizing.edge_length_near_solids = 0.025 * size;
    sizing.grading_distance = 0.3 * size;
    in_child([&] { run_case("bunny in box, graded", bunny, box_lo, box_hi, sizing, v_bunny, "input surface"); });
  }
  // Sphere r = 0.3 in [-0.6, 0.6]^3 (icosphere level 5, 20480 triangles).
  {
    const double r = 0.3;
    const SurfaceMesh sphere = make_sphere(r, 5);
    MeshSizing sizing;
    sizing.edge_length = 0.042;
    in_child([&] {
      run_case("sphere r=0.3 in box", sphere, {-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}, sizing, 4.0 / 3.0 * M_PI * r * r * r,
               "4/3 pi r^3");
    });
  }
}

void remesh_cases(const std::string& filter) {
  // Per-step fluid remeshing (remesher.hpp): sphere r = 0.3 in [-0.6, 0.6]^3 meshed uniformly with
  // h for ~25k, 100k and 400k tets, moved by 0.1 h, then the fluid remeshed to its mean edge length
  // (a band of 3 h at every size; the whole fluid at 100k; and "move, remesh when needed" at 100k).
  // Error column: fluid min dihedral after the step, the phases, and whether the solid tets came
  // back identical.
  struct RemeshCase {
    const char* name;
    double h, band_cells;
    bool only_when_needed;
    int iterations = 2;
  };
  for (const RemeshCase& c : {RemeshCase{"remesh step, band 3h, ~25k", 0.0667, 3.0, false},
                              RemeshCase{"remesh step, band 3h, ~100k", 0.042, 3.0, false},
                              RemeshCase{"remesh step, band 3h, ~400k", 0.0265, 3.0, false},
                              RemeshCase{"remesh step, band 3h, 1 iteration, ~100k", 0.042, 3.0, false, 1},
                              RemeshCase{"remesh step, whole fluid, ~100k", 0.042, 0.0, false},
                              RemeshCase{"move, remesh when needed, ~100k", 0.042, 3.0, true}}) {
    if (std::string(c.name).find(filter) == std::string::npos) continue;
    in_child([&] {
      MeshSizing sizing;
      sizing.edge_length = c.h;
      const TetMesh m = build_complex({-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}, {make_sphere(0.3, 5)}, sizing);
      std::vector<Eigen::Vector3d> target = m.vertices;
      std::vector<char> solid(m.vertices.size(), 0);
      for (int t = 0; t < m.num_tets(); ++t)
        if (m.subdomain[t] != kFluidSubdomain)
          for (int v : m.tets[t]) solid[v] = 1;
      for (std::size_t v = 0; v < target.size(); ++v)
        if (solid[v]) target[v].x() += 0.1 * c.h;
      RemeshOptions options;
      options.target_edge_length = mean_edge_length(m, kFluidSubdomain);
      options.band = c.band_cells * c.h;
      options.remesh_only_when_needed = c.only_when_needed;
      options.iterations = c.iterations;
      bench::Stopwatch clock;
      const RemeshResult r = remesh_step(m, target, options);
      const double seconds = clock.seconds();
      int solid_before = 0, solid_after = 0;
      for (int label : m.subdomain) solid_before += (label != kFluidSubdomain);
      for (int label : r.mesh.subdomain) solid_after += (label != kFluidSubdomain);
      const RemeshReport& p = r.report;
      char err[400], res[120];
      std::snprintf(err, sizeof err,
                    "fluid min dihedral %.1f deg, max %.1f; %s %d fluid tets%s (%d tets in CGAL) in %d pass(es); "
                    "phases [s]: motion %.2f, "
                    "build %.2f, cgal %.2f, copy %.2f, sliver pass %.2f, check %.2f; solid tets %d -> %d; %s",
                    p.min_dihedral_deg, p.max_dihedral_deg, p.remeshed ? "remeshed" : "NOT remeshed (moved only),",
                    p.remeshed ? p.remeshed_fluid_tets : 0, p.local ? " (band alone to CGAL)" : "",
                    p.remeshed ? p.region_tets : 0, p.passes, p.motion_seconds, p.build_seconds,
                    p.cgal_seconds, p.copy_seconds, p.sliver_seconds, p.check_seconds, solid_before, solid_after,
                    check_interface(r.mesh).conforming() ? "interface conforming" : "INTERFACE NOT CONFORMING");
      std::snprintf(res, sizeof res, "%d -> %d tets, h = %.4g m", m.num_tets(), r.mesh.num_tets(), c.h);
      bench::print_row(c.name, res, err, seconds);
    });
  }
  // "Move, remesh when needed" over 10 steps of 0.25 h each, band 2 h around the spoiled tets
  // (adaptive_band): seconds per step (mean and worst) and how many steps were remeshed.
  for (const auto& [name, h] : {std::pair{"10 steps, remesh when needed, adaptive band, ~100k", 0.042},
                                std::pair{"10 steps, remesh when needed, adaptive band, ~400k", 0.0265}}) {
    if (std::string(name).find(filter) == std::string::npos) continue;
    in_child([&, name = name, h = h] {
      MeshSizing sizing;
      sizing.edge_length = h;
      TetMesh m = build_complex({-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}, {make_sphere(0.3, 5)}, sizing);
      const int tets_before = m.num_tets();
      RemeshOptions options;
      options.target_edge_length = mean_edge_length(m, kFluidSubdomain);
      options.band = 2.0 * h;
      options.remesh_only_when_needed = true;
      options.adaptive_band = true;
      double total = 0.0, worst = 0.0, worst_dihedral = 180.0, cgal = 0.0;
      int remeshed = 0, remeshed_tets = 0;
      bench::Stopwatch clock;
      for (int step = 0; step < 10; ++step) {
        std::vector<Eigen::Vector3d> target = m.vertices;
        std::vector<char> solid(m.vertices.size(), 0);
        for (int t = 0; t < m.num_tets(); ++t)
          if (m.subdomain[t] != kFluidSubdomain)
            for (int v : m.tets[t]) solid[v] = 1;
        for (std::size_t v = 0; v < target.size(); ++v)
          if (solid[v]) target[v].x() += 0.25 * h;
        RemeshResult r = remesh_step(m, target, options);
        total += r.report.seconds;
        worst = std::max(worst, r.report.seconds);
        cgal += r.report.cgal_seconds;
        worst_dihedral = std::min(worst_dihedral, r.report.min_dihedral_deg);
        remeshed += r.report.remeshed;
        if (r.report.remeshed) remeshed_tets = std::max(remeshed_tets, r.report.remeshed_fluid_tets);
        m = std::move(r.mesh);
      }
      const double seconds = clock.seconds();
      char err[400], res[120];
      std::snprintf(err, sizeof err,
                    "fluid min dihedral >= %.1f deg; remeshed %d of 10 steps (at most %d fluid tets); per step [s]: "
                    "mean %.2f, worst %.2f (cgal %.2f in all); %s",
                    worst_dihedral, remeshed, remeshed_tets, total / 10, worst, cgal,
                    check_interface(m).conforming() ? "interface conforming" : "INTERFACE NOT CONFORMING");
      std::snprintf(res, sizeof res, "%d -> %d tets, h = %.4g m", tets_before, m.num_tets(), h);
      bench::print_row(name, res, err, seconds);
    });
  }
}

}  // namespace

int main(int argc, char** argv) {
  const bool remesh_only = argc > 1 && std::string(argv[1]) == "--remesh-only";
  const std::string bunny_path = argc > 1 && !remesh_only ? argv[1] : TETFSI_SHARED_DIR "/data/bunny.obj";
  SurfaceMesh bunny = import_surface(bunny_path);
  validate_surface(bunny, bunny_path);
  Eigen::Vector3d lo, hi;
  bounding_box(bunny, lo, hi);
  const double size = (hi - lo).maxCoeff();
  const Eigen::Vector3d box_lo = lo.array() - 0.25 * size, box_hi = hi.array() + 0.25 * size;
  const double v_bunny = enclosed_volume(bunny);

  bench::print_header();
  if (!remesh_only) complex_cases(bunny, box_lo, box_hi, size, v_bunny);
  remesh_cases(remesh_only && argc > 2 ? argv[2] : "");
  return 0;
}
