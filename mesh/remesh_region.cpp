/// @file remesh_region.cpp
/// Band and CGAL region of a band remesh (remesh_region.hpp). Face, edge and fan bookkeeping by
/// sorting vectors of keys (no hash maps: deterministic and, at 10^5 tets, a few ms).
#include "mesh/remesh_region.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <set>

#include "mesh/incidence.hpp"
#include "mesh/interface.hpp"  // kTetFaceVertices

namespace tetfsi::mesh {
namespace {
std::vector<std::array<int, 3>> hull_triangles(const TetMesh& mesh, const std::vector<char>& region);
}  // namespace

std::vector<int> vertex_kinds(const TetMesh& mesh) {
  std::vector<int> kind(mesh.num_vertices(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain[t] != kFluidSubdomain)
      for (int v : mesh.tets[t]) kind[v] = 1;
  const std::vector<char> all(mesh.tets.size(), 1);
  for (const auto& f : hull_triangles(mesh, all))
    for (int v : f)
      if (kind[v] == 0) kind[v] = 2;
  return kind;
}

std::vector<char> band_tets(const TetMesh& mesh, double band, const std::vector<char>& seeds) {
  const int n = mesh.num_vertices();
  std::vector<char> selected(mesh.tets.size(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) selected[t] = mesh.subdomain[t] == kFluidSubdomain;
  if (!(band > 0.0)) return selected;
  std::vector<char> is_solid(n, 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain[t] != kFluidSubdomain)
      for (int v : mesh.tets[t]) is_solid[v] = 1;
  std::vector<Eigen::Vector3d> solid_points;  // the seed points
  for (int v = 0; v < n; ++v)
    if (seeds.empty() ? is_solid[v] : seeds[v]) solid_points.push_back(mesh.vertices[v]);
  // Distance by brute force over solid vertices, only for vertices in the solids' bounding box
  // grown by the band (the others are farther than the band anyway).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : solid_points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= band;
  hi.array() += band;
  std::vector<char> near(n, 0);
  const double b2 = band * band;
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
    selected[t] = selected[t] && (near[tet[0]] || near[tet[1]] || near[tet[2]] || near[tet[3]]);
  }
  return selected;
}

std::vector<char> resized_tets(const TetMesh& mesh, const SizeField& size_then, const SizeField& size_now,
                               double ratio, int rings) {
  std::vector<char> in_fluid(mesh.num_vertices(), 0), moved(mesh.num_vertices(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (mesh.subdomain[t] == kFluidSubdomain)
      for (int v : mesh.tets[t]) in_fluid[v] = 1;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!in_fluid[v]) continue;
    const double then = size_then(mesh.vertices[v]), now = size_now(mesh.vertices[v]);
    moved[v] = now > ratio * then || now * ratio < then;
  }
  std::vector<char> flagged(mesh.tets.size(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto& v = mesh.tets[t];
    flagged[t] = mesh.subdomain[t] == kFluidSubdomain && (moved[v[0]] || moved[v[1]] || moved[v[2]] || moved[v[3]]);
  }
  const VertexIncidence around = vertex_incidence(mesh);
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<char> grown = flagged;
    for (int t = 0; t < mesh.num_tets(); ++t) {
      if (!flagged[t]) continue;
      for (int v : mesh.tets[t])
        for (int k = around.start[v]; k < around.start[v + 1]; ++k)
          if (mesh.subdomain[around.element[k]] == kFluidSubdomain) grown[around.element[k]] = 1;
    }
    flagged = std::move(grown);
  }
  return flagged;
}

namespace {

/// Root of x in a union-find forest stored in `parent` (path halving).
int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// Hull triangles (sorted vertex triples) of the tets flagged in `region`: faces seen once.
std::vector<std::array<int, 3>> hull_triangles(const TetMesh& mesh, const std::vector<char>& region) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(4 * static_cast<std::size_t>(std::count(region.begin(), region.end(), 1)));
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!region[t]) continue;
    for (const auto& f : kTetFaceVertices) {
      std::array<int, 3> key{mesh.tets[t][f[0]], mesh.tets[t][f[1]], mesh.tets[t][f[2]]};
      std::sort(key.begin(), key.end());
      faces.push_back(key);
    }
  }
  // Equal keys are equal elements, so the parallel sort's result does not depend on the threads.
  tbb::parallel_sort(faces.begin(), faces.end());
  std::vector<std::array<int, 3>> hull;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1) hull.push_back(faces[i]);
    i = j;
  }
  return hull;
}

/// Vertices where the hull is not a 2-manifold: an end of an edge in other than two hull
/// triangles, or a vertex whose hull triangles form more than one fan (link cycle).
std::vector<int> non_manifold_vertices(const std::vector<std::array<int, 3>>& hull) {
  std::vector<int> bad;
  std::vector<std::array<int, 2>> edges;
  // Link of each vertex: (vertex, link edge end a, link edge end b).
  std::vector<std::array<int, 3>> link;
  for (const auto& f : hull)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
      link.push_back({a, std::min(b, c), std::max(b, c)});
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i != 2) bad.insert(bad.end(), edges[i].begin(), edges[i].end());
    i = j;
  }
  std::sort(link.begin(), link.end());
  std::vector<int> ends, parent;
  for (std::size_t i = 0; i < link.size();) {
    std::size_t j = i;
    while (j < link.size() && link[j][0] == link[i][0]) ++j;
    ends.clear();
    for (std::size_t k = i; k < j; ++k) ends.insert(ends.end(), {link[k][1], link[k][2]});
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    parent.resize(ends.size());
    std::iota(parent.begin(), parent.end(), 0);
    int components = static_cast<int>(ends.size());
    for (std::size_t k = i; k < j; ++k) {
      const int a = find_root(parent, int(std::lower_bound(ends.begin(), ends.end(), link[k][1]) - ends.begin()));
      const int b = find_root(parent, int(std::lower_bound(ends.begin(), ends.end(), link[k][2]) - ends.begin()));
      if (a != b) {
        parent[a] = b;
        --components;
      }
    }
    if (components != 1) bad.push_back(link[i][0]);
    i = j;
  }
  std::sort(bad.begin(), bad.end());
  bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
  return bad;
}

}  // namespace

bool region_is_ball(const TetMesh& mesh, const std::vector<char>& region) {
  // Euler characteristic of the region, chi = V - E + F - C, and of its hull surface,
  // chi_h = V_h - E_h + F_h, from the distinct vertices, edges and faces of the region's tets.
  using Edge = std::array<int, 2>;
  using Face = std::array<int, 3>;
  std::set<int> vertices, hull_vertices;
  std::set<Edge> edges, hull_edges;
  std::map<Face, int> faces;  // face -> number of region tets having it
  long cells = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!region[t]) continue;
    ++cells;
    const auto& v = mesh.tets[t];
    for (int a = 0; a < 4; ++a) {
      vertices.insert(v[a]);
      for (int b = a + 1; b < 4; ++b) edges.insert({std::min(v[a], v[b]), std::max(v[a], v[b])});
    }
    for (int skip = 0; skip < 4; ++skip) {
      Face f{};
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != skip) f[n++] = v[k];
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  }
  long hull_faces = 0;
  for (const auto& [f, count] : faces) {
    if (count != 1) continue;
    ++hull_faces;
    for (int a = 0; a < 3; ++a) {
      hull_vertices.insert(f[a]);
      const int b = f[(a + 1) % 3];
      hull_edges.insert({std::min(f[a], b), std::max(f[a], b)});
    }
  }
  const long chi = long(vertices.size()) - long(edges.size()) + long(faces.size()) - cells;
  const long chi_hull = long(hull_vertices.size()) - long(hull_edges.size()) + hull_faces;
  return cells > 0 && chi == 1 && chi_hull == 2;
}

std::vector<char> band_region(const TetMesh& mesh, const std::vector<char>& band, int max_rounds) {
  const int n = mesh.num_vertices();
  // Vertex -> incident tets (compressed rows).
  const VertexIncidence tets_around = vertex_incidence(mesh);
  const std::vector<int>& start = tets_around.start;
  const std::vector<int>& incident = tets_around.element;
  std::vector<char> region(mesh.tets.size(), 0);
  const auto add_star = [&](int v) {
    for (int k = start[v]; k < start[v + 1]; ++k) region[incident[k]] = 1;
  };
  std::vector<char> touched(n, 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.subdomain[t] != kFluidSubdomain) region[t] = 1;
    if (band[t])
      for (int v : mesh.tets[t]) touched[v] = 1;
  }
  for (int v = 0; v < n; ++v)
    if (touched[v]) add_star(v);
  for (int round = 0; round < max_rounds; ++round) {
    const std::vector<int> bad = non_manifold_vertices(hull_triangles(mesh, region));
    if (bad.empty()) return region_is_ball(mesh, region) ? region : std::vector<char>{};
    for (int v : bad) add_star(v);
  }
  return {};
}

}  // namespace tetfsi::mesh
