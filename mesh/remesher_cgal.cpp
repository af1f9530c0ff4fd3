/// @file remesher_cgal.cpp
/// The CGAL tetrahedral-remeshing translation unit of remesher.hpp: remesh_fluid().
///
/// CGAL 5.5.1's tetrahedral_isotropic_remeshing with remesh_boundaries(false) keeps the facets
/// between different subdomains, but still edits unselected cells that are in the complex. So the
/// solid tets (and, with a band, the fluid tets outside it) are relabelled 0 ("outside") during
/// the call and given back their labels afterwards, found again by their four vertices
/// (shared/references/dependencies.md, section 2).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_3/tet_soup_to_c3t3.h>
#include <CGAL/Tetrahedral_remeshing/Remeshing_triangulation_3.h>
#include <CGAL/tetrahedral_remeshing.h>

#include <algorithm>
#include <map>

#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/remesher.hpp"

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

}  // namespace

RemeshResult remesh_fluid(const TetMesh& mesh, const RemeshOptions& options, int iterations) {
  if (!(options.target_edge_length > 0.0)) throw MeshError("remesh: target_edge_length must be > 0");
  const int n = mesh.num_vertices();

  // Which fluid tets are remeshed: all, or those with a vertex within `band` of a solid vertex.
  std::vector<char> selected(mesh.tets.size(), 1);
  if (options.band > 0.0) {
    std::vector<Eigen::Vector3d> solid_points;
    std::vector<char> is_solid(n, 0);
    for (int t = 0; t < mesh.num_tets(); ++t)
      if (mesh.subdomain[t] != kFluidSubdomain)
        for (int v : mesh.tets[t]) is_solid[v] = 1;
    for (int v = 0; v < n; ++v)
      if (is_solid[v]) solid_points.push_back(mesh.vertices[v]);
    // Distance by brute force over solid vertices, only for vertices in the solids' bounding box
    // grown by the band (the others are farther than the band anyway).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto& p : solid_points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    lo.array() -= options.band;
    hi.array() += options.band;
    std::vector<char> near(n, 0);
    const double b2 = options.band * options.band;
    for (int v = 0; v < n; ++v) {
      const auto& x = mesh.vertices[v];
      if (!((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all())) continue;
      for (const auto& p : solid_points)
        if ((x - p).squaredNorm() <= b2) {
          near[v] = 1;
          break;
        }
    }
    for (int t = 0; t < mesh.num_tets(); ++t) {
      const auto& tet = mesh.tets[t];
      selected[t] = near[tet[0]] || near[tet[1]] || near[tet[2]] || near[tet[3]];
    }
  }

  // Hide the solid and the unselected fluid as subdomain 0; remember them by vertex 4-tuples.
  std::vector<Tr::Point> points;
  points.reserve(n);
  for (const auto& x : mesh.vertices) points.emplace_back(x.x(), x.y(), x.z());
  std::vector<std::array<int, 5>> cells;
  cells.reserve(mesh.tets.size());
  std::map<Key, int> hidden;  // sorted vertices -> label to restore
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto& v = mesh.tets[t];
    int label = mesh.subdomain[t];
    if (label != kFluidSubdomain || !selected[t]) {
      hidden.emplace(sorted(v), label);
      label = 0;
    }
    cells.push_back({v[0], v[1], v[2], v[3], label});
  }
  Tr tr;
  std::vector<Vh> handles;
  if (!CGAL::build_triangulation<Tr, false>(tr, points, cells, {}, handles))
    throw MeshError("remesh: the tet mesh is not a valid triangulation (not conforming, or not convex)");
  std::map<Vh, int> old_index;
  for (int v = 0; v < n; ++v) old_index.emplace(handles[v + 1], v);

  CGAL::tetrahedral_isotropic_remeshing(
      tr, options.target_edge_length,
      CGAL::parameters::remesh_boundaries(false).number_of_iterations(static_cast<std::size_t>(iterations)));

  // Back to plain arrays: vertices in the order of first use by a cell; hidden tets restored.
  RemeshResult result;
  std::map<Vh, int> index;
  std::size_t restored = 0;
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) {
    std::array<int, 4> tet{};
    std::array<int, 4> old{};
    bool all_old = true;
    for (int k = 0; k < 4; ++k) {
      const Vh vh = c->vertex(k);
      auto it = index.find(vh);
      if (it == index.end()) {
        it = index.emplace(vh, result.mesh.num_vertices()).first;
        const auto& p = tr.point(vh);
        result.mesh.vertices.emplace_back(p.x(), p.y(), p.z());
        const auto o = old_index.find(vh);
        result.old_index.push_back(o == old_index.end() ? -1 : o->second);
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
  return result;
}

}  // namespace tetfsi::mesh
