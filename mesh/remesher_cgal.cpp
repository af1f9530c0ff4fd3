/// @file remesher_cgal.cpp
/// The CGAL tetrahedral-remeshing translation unit of remesher.hpp: remesh_fluid().
///
/// CGAL 5.5.1's tetrahedral_isotropic_remeshing with remesh_boundaries(false) keeps the facets
/// between different subdomains, but still edits unselected cells that are in the complex. So the
/// solid tets (and, with a band, the fluid tets outside it) are relabelled 0 ("outside") during
/// the call and given back their labels afterwards, found again by their four vertices. With a
/// band, only the regions of remesh_region.hpp (band, a ring of hidden tets, the solids it reaches;
/// one triangulation per piece) are built into triangulations; the other tets are copied over
/// unchanged.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_3/tet_soup_to_c3t3.h>
#include <CGAL/Tetrahedral_remeshing/Remeshing_triangulation_3.h>
#include <CGAL/exceptions.h>
#include <CGAL/tetrahedral_remeshing.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <unordered_map>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/remesher.hpp"
#include "mesh/remesh_region.hpp"

namespace tetfsi::mesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Tr = CGAL::Tetrahedral_remeshing::Remeshing_triangulation_3<K>;
using Vh = Tr::Vertex_handle;
using Key = std::array<int, 4>;  // sorted input vertex indices of a hidden tet

Key sorted(std::array<int, 4> k) {
  std::sort(k.begin(), k.end());
  return k;
}

/// Builds CGAL's triangulation of the tets flagged in `in_region` (the unselected ones hidden as
/// label 0), remeshes it and appends its cells to `result` (vertices through `add_vertex`, which
/// maps mesh vertices to result vertices). Returns false, with `result` untouched, if the region is
/// not a valid triangulation (not a ball, or not conforming).
template <class AddVertex>
bool remesh_one_region(const TetMesh& mesh, const RemeshOptions& options, int iterations,
                       const std::vector<char>& in_region, const std::vector<char>& selected, RemeshResult& result,
                       const AddVertex& add_vertex) {
  const auto t_start = std::chrono::steady_clock::now();
  Tr tr;
  std::vector<int> to_global;  // CGAL input vertex -> mesh vertex
  std::map<Key, int> hidden;   // sorted mesh vertices -> label to restore
  std::vector<int> to_local(mesh.num_vertices(), -1);
  std::vector<Tr::Point> points;
  std::vector<std::array<int, 5>> cells;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!in_region[t]) continue;
    const auto& v = mesh.tets[t];
    std::array<int, 5> cell{};
    for (int k = 0; k < 4; ++k) {
      if (to_local[v[k]] < 0) {
        to_local[v[k]] = static_cast<int>(to_global.size());
        to_global.push_back(v[k]);
        const auto& x = mesh.vertices[v[k]];
        points.emplace_back(x.x(), x.y(), x.z());
      }
      cell[k] = to_local[v[k]];
    }
    int label = mesh.subdomain[t];
    if (!selected[t]) {
      hidden.emplace(sorted(v), label);
      label = 0;
    }
    cell[4] = label;
    cells.push_back(cell);
  }
  std::vector<Vh> handles;
  if (!CGAL::build_triangulation<Tr, false>(tr, points, cells, {}, handles, false) || handles.empty()) return false;
  result.report.region_tets += static_cast<int>(cells.size());
  std::unordered_map<Vh, int> old_index;
  for (std::size_t v = 0; v < to_global.size(); ++v) old_index.emplace(handles[v + 1], to_global[v]);
  const auto t_built = std::chrono::steady_clock::now();

  const auto params =
      CGAL::parameters::remesh_boundaries(false).number_of_iterations(static_cast<std::size_t>(iterations));
  if (options.size_at) {
    const double target = options.target_edge_length;
    const auto& size_at = options.size_at;
    CGAL::tetrahedral_isotropic_remeshing(
        tr, [&](const Tr::Point& q) { return std::min(target, size_at(Eigen::Vector3d(q.x(), q.y(), q.z()))); }, params);
  } else {
    CGAL::tetrahedral_isotropic_remeshing(tr, options.target_edge_length, params);
  }
  const auto t_remeshed = std::chrono::steady_clock::now();

  // Back to plain arrays: vertices in the order of first use by a cell; hidden tets restored.
  std::unordered_map<Vh, int> index;
  std::size_t restored = 0;
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) {
    std::array<int, 4> tet{};
    std::array<int, 4> old{};
    bool all_old = true;
    for (int k = 0; k < 4; ++k) {
      const Vh vh = c->vertex(k);
      auto it = index.find(vh);
      if (it == index.end()) {
        const auto& p = tr.point(vh);
        const auto o = old_index.find(vh);
        it = index.emplace(vh, add_vertex({p.x(), p.y(), p.z()}, o == old_index.end() ? -1 : o->second)).first;
      }
      tet[k] = it->second;
      old[k] = result.old_index[it->second];
      all_old = all_old && old[k] >= 0;
    }
    int label = c->subdomain_index();
    if (label == 0) {
      const auto h = all_old ? hidden.find(sorted(old)) : hidden.end();
      if (h == hidden.end()) throw MeshError("remesh: CGAL changed a hidden (solid or out-of-band) tet");
      label = h->second;
      ++restored;
    }
    result.mesh.tets.push_back(tet);
    if (signed_volume(result.mesh, result.mesh.num_tets() - 1) < 0.0)
      std::swap(result.mesh.tets.back()[0], result.mesh.tets.back()[1]);
    result.mesh.subdomain.push_back(label);
  }
  if (restored != hidden.size())
    throw MeshError("remesh: " + std::to_string(hidden.size() - restored) + " hidden tets were lost by CGAL");
  const auto t_done = std::chrono::steady_clock::now();
  result.report.build_seconds += std::chrono::duration<double>(t_built - t_start).count();
  result.report.cgal_seconds += std::chrono::duration<double>(t_remeshed - t_built).count();
  result.report.copy_seconds += std::chrono::duration<double>(t_done - t_remeshed).count();
  return true;
}

RemeshResult remesh_fluid_unguarded(const TetMesh& mesh, const RemeshOptions& options, int iterations,
                                    const std::vector<char>& seeds) {
  if (!(options.target_edge_length > 0.0)) throw MeshError("remesh: target_edge_length must be > 0");
  const auto t_start = std::chrono::steady_clock::now();
  const int n = mesh.num_vertices();

  // Which fluid tets are remeshed (band_tets) and which tets CGAL gets (band_regions: one
  // triangulation per piece; the whole mesh without a band, or if a piece does not make a valid
  // triangulation).
  std::vector<char> selected;
  if (options.remesh_tets.empty()) {
    selected = band_tets(mesh, options.band, seeds);
  } else {
    if (options.remesh_tets.size() != mesh.tets.size()) throw MeshError("remesh: remesh_tets does not match the mesh");
    selected.assign(mesh.tets.size(), 0);
    for (int t = 0; t < mesh.num_tets(); ++t) selected[t] = options.remesh_tets[t] && mesh.subdomain[t] == kFluidSubdomain;
  }
  std::vector<std::vector<char>> regions;
  if (options.band > 0.0 || !options.remesh_tets.empty()) regions = band_regions(mesh, selected);
  const double regions_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  RemeshResult result;
  std::vector<int> new_of_old(n, -1);
  const auto add_vertex = [&](const Eigen::Vector3d& x, int old) {
    result.mesh.vertices.push_back(x);
    result.old_index.push_back(old);
    if (old >= 0) new_of_old[old] = result.mesh.num_vertices() - 1;
    return result.mesh.num_vertices() - 1;
  };
  // CGAL's cells first (region by region), then the tets left out of CGAL.
  bool local = !regions.empty();
  for (const std::vector<char>& region : regions)
    if (!remesh_one_region(mesh, options, iterations, region, selected, result, add_vertex)) {
      local = false;
      break;
    }
  if (!local) {
    result = RemeshResult{};
    std::fill(new_of_old.begin(), new_of_old.end(), -1);
    regions.assign(1, std::vector<char>(mesh.tets.size(), 1));
    if (!remesh_one_region(mesh, options, iterations, regions[0], selected, result, add_vertex))
      throw MeshError("remesh: the tet mesh is not a valid triangulation (not conforming, or not convex)");
  }
  const auto t_copy = std::chrono::steady_clock::now();
  result.report.local = local;
  std::vector<char> in_any(mesh.tets.size(), 0);
  for (const std::vector<char>& region : regions)
    for (int t = 0; t < mesh.num_tets(); ++t) in_any[t] = in_any[t] || region[t];
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (in_any[t]) continue;
    std::array<int, 4> tet = mesh.tets[t];
    for (int& v : tet) v = new_of_old[v] >= 0 ? new_of_old[v] : add_vertex(mesh.vertices[v], v);
    result.mesh.tets.push_back(tet);
    result.mesh.subdomain.push_back(mesh.subdomain[t]);
  }
  result.report.build_seconds += regions_seconds;
  result.report.copy_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_copy).count();
  for (int t = 0; t < mesh.num_tets(); ++t)
    result.report.remeshed_fluid_tets += mesh.subdomain[t] == kFluidSubdomain && selected[t];
  return result;
}

}  // namespace

RemeshResult remesh_fluid(const TetMesh& mesh, const RemeshOptions& options, int iterations,
                          const std::vector<char>& seeds) {
  try {
    return remesh_fluid_unguarded(mesh, options, iterations, seeds);
  } catch (const CGAL::Failure_exception& e) {  // a CGAL assertion, precondition or error
    throw MeshError("remesh: CGAL tetrahedral remeshing failed (" + e.message() +
                    (e.expression().empty() ? "" : ": " + e.expression()) + ")");
  }
}

}  // namespace tetfsi::mesh
