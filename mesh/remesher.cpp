/// @file remesher.cpp
/// The step driver of remesher.hpp (mesh motion in mesh_motion.cpp (the CGAL call is in remesher_cgal.cpp).
#include "mesh/remesher.hpp"

#include <algorithm>
#include <sstream>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/interface.hpp"
#include "mesh/mesh_motion.hpp"
#include "mesh/quality.hpp"
#include "mesh/remesh_region.hpp"
#include "mesh/sliver_perturbation.hpp"
#include "support/stopwatch.hpp"

namespace tetfsi::mesh {

namespace {

/// Fluid tets of the moved mesh that fail RemeshOptions::remesh_only_when_needed's check: fluid
/// min dihedral below the threshold, flat or inverted, or volume changed by more than a factor.
/// `angles` gets the min and max dihedral angle [deg] over the good fluid tets.
std::vector<int> spoiled_fluid_tets(const TetMesh& before, const TetMesh& moved, const RemeshOptions& options,
                                    std::array<double, 2>& angles) {
  std::vector<int> out;
  angles = {180.0, 0.0};
  for (int t = 0; t < moved.num_tets(); ++t) {
    if (moved.subdomain[t] != kFluidSubdomain) continue;
    const auto& v = moved.tets[t];
    const auto& x = moved.vertices;
    const double ratio = signed_volume(moved, t) / signed_volume(before, t);
    bool bad = flat_or_inverted(x[v[0]], x[v[1]], x[v[2]], x[v[3]]) ||
               !(ratio <= options.max_volume_ratio && ratio * options.max_volume_ratio >= 1.0);
    if (!bad) {
      const auto a = dihedral_angles_deg(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
      const auto [lo, hi] = std::minmax_element(a.begin(), a.end());
      bad = *lo < options.min_dihedral_deg;
      angles = {std::min(angles[0], *lo), std::max(angles[1], *hi)};
    }
    if (bad) out.push_back(t);
  }
  return out;
}

}  // namespace

RemeshResult remesh_step(const TetMesh& mesh, const std::vector<Eigen::Vector3d>& solid_positions,
                         const RemeshOptions& options) {
  const Stopwatch start;
  TetMesh moved = mesh;
  moved.vertices = move_with_solids(mesh, solid_positions, options.motion);
  // Tets the motion made flat or inverted (a tet already flat in the input, e.g. a sliver Mesh_3
  // left inside a thin solid, is not the motion's fault and is left alone).
  int spoiled = 0, spoiled_fluid = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto& v = mesh.tets[t];
    const auto bad = [&](const TetMesh& m) {
      return flat_or_inverted(m.vertices[v[0]], m.vertices[v[1]], m.vertices[v[2]], m.vertices[v[3]]);
    };
    if (bad(moved) && !bad(mesh)) {
      ++spoiled;
      spoiled_fluid += mesh.subdomain[t] == kFluidSubdomain;
    }
  }
  if (spoiled > 0)
    throw MeshError("remesh: the solid motion inverts or flattens " + std::to_string(spoiled) + " tets (" +
                    std::to_string(spoiled_fluid) + " fluid); take a smaller step");
  const double motion_seconds = start.seconds();
  RemeshResult result;
  double build = 0, cgal = 0, copy = 0, sliver = 0, check = 0;
  std::vector<char> seeds;
  if (options.remesh_only_when_needed) {
    const Stopwatch t;
    std::array<double, 2> angles{};
    const std::vector<int> spoiled = spoiled_fluid_tets(mesh, moved, options, angles);
    if (options.adaptive_band && !spoiled.empty()) {
      seeds.assign(moved.vertices.size(), 0);
      for (int s : spoiled)
        for (int v : moved.tets[s]) seeds[v] = 1;
    }
    check += t.seconds();
    if (spoiled.empty()) {
      result.mesh = std::move(moved);
      result.old_index.resize(result.mesh.vertices.size());
      for (std::size_t v = 0; v < result.old_index.size(); ++v) result.old_index[v] = static_cast<int>(v);
      result.report.remeshed = false;
      result.report.passes = 0;
      result.report.min_dihedral_deg = angles[0];
      result.report.max_dihedral_deg = angles[1];
      result.report.quality_ok = true;
    }
  }
  // Fallback chain when the quality check fails: each further pass has one more CGAL iteration and,
  // with a band, twice the band of the pass before; from the third pass on, the whole fluid.
  const int passes = std::max(1, options.max_passes);
  for (int pass = 1; result.report.remeshed && pass <= passes; ++pass) {
    RemeshOptions opt = options;
    opt.band = pass >= 3 ? 0.0 : options.band * (1 << (pass - 1));
    if (pass >= 2) opt.remesh_tets.clear();
    result = remesh_fluid(moved, opt, options.iterations + pass - 1, seeds);
    build += result.report.build_seconds;
    cgal += result.report.cgal_seconds;
    copy += result.report.copy_seconds;
    if (options.sliver_pass_below_deg > 0.0) {
      const Stopwatch t;
      const SliverPassReport s = perturb_slivers(result.mesh, options.sliver_pass_below_deg);
      result.report.slivers_before = s.slivers_before;
      result.report.slivers_after = s.slivers_after;
      sliver += t.seconds();
    }
    const Stopwatch t;
    const QualityReport q = quality_report(result.mesh, kFluidSubdomain);
    check += t.seconds();
    result.report.passes = pass;
    result.report.min_dihedral_deg = q.min_dihedral_deg;
    result.report.max_dihedral_deg = q.max_dihedral_deg;
    result.report.quality_ok = q.min_dihedral_deg >= options.min_dihedral_deg && q.inverted + q.degenerate == 0;
    if (result.report.quality_ok) break;
  }
  result.report.num_tets = result.mesh.num_tets();
  result.report.num_fluid_tets = 0;
  for (int label : result.mesh.subdomain) result.report.num_fluid_tets += (label == kFluidSubdomain);
  result.report.motion_seconds = motion_seconds;
  result.report.build_seconds = build;
  result.report.cgal_seconds = cgal;
  result.report.copy_seconds = copy;
  result.report.sliver_seconds = sliver;
  result.report.check_seconds = check;
  result.report.seconds = start.seconds();
  return result;
}

std::string RemeshReport::summary() const {
  std::ostringstream s;
  s.precision(4);
  s << num_tets << " tets (" << num_fluid_tets << " fluid), fluid dihedral [" << min_dihedral_deg << ", "
    << max_dihedral_deg << "] deg, ";
  if (remeshed)
    s << passes << " pass(es) on " << remeshed_fluid_tets << " fluid tets" << (local ? " (band)" : "")
      << ", sliver pass " << slivers_before << " -> " << slivers_after << ", ";
  else
    s << "moved only (no remesh needed), ";
  s << (quality_ok ? "ok" : "BELOW THRESHOLD") << ", "
    << seconds << " s";
  return s.str();
}

}  // namespace tetfsi::mesh
