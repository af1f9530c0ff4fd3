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

/// Flags in `reached` (and marks in `seen`) the tets connected to `seed` through shared vertices
/// among the tets that pass `admit`; `seed` must pass it and not be seen yet.
template <class Admit>
void flood_through_vertices(const TetMesh& mesh, const VertexIncidence& tets_around, int seed, const Admit& admit,
                            std::vector<char>& seen, std::vector<char>& reached) {
  std::vector<int> stack{seed};
  seen[seed] = 1;
  while (!stack.empty()) {
    const int u = stack.back();
    stack.pop_back();
    reached[u] = 1;
    for (int v : mesh.tets[u])
      for (int k = tets_around.start[v]; k < tets_around.start[v + 1]; ++k) {
        const int w = tets_around.element[k];
        if (admit(w) && !seen[w]) seen[w] = 1, stack.push_back(w);
      }
  }
}

/// Adds to `region` every solid it reaches (a solid tet sharing a vertex with a region tet),
/// whole: its tets connected through shared vertices. A band around a solid without the solid is
/// a shell, not a ball; a solid the region does not reach stays out, so a region far from the
/// solids (a refit to a liquid surface, resized_tets) stays one piece instead of two, which would
/// send the whole mesh to CGAL.
void add_reached_solids(const TetMesh& mesh, const VertexIncidence& tets_around, std::vector<char>& region) {
  std::vector<char> on_region(mesh.num_vertices(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (region[t])
      for (int v : mesh.tets[t]) on_region[v] = 1;
  const auto is_solid = [&](int t) { return mesh.subdomain[t] != kFluidSubdomain; };
  std::vector<char> seen(mesh.tets.size(), 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto& tet = mesh.tets[t];
    if (is_solid(t) && !seen[t] && std::any_of(tet.begin(), tet.end(), [&](int v) { return on_region[v] != 0; }))
      flood_through_vertices(mesh, tets_around, t, is_solid, seen, region);
  }
}

/// Adds to `region` the tets of its complement that cannot be reached from the mesh's hull
/// through faces of complement tets (the cavities the region encloses). Returns false if there
/// was none to add.
bool fill_cavities(const TetMesh& mesh, std::vector<char>& region) {
  struct FaceOfTet {
    std::array<int, 3> key;
    int tet;
    bool operator<(const FaceOfTet& o) const { return key < o.key || (key == o.key && tet < o.tet); }
  };
  std::vector<FaceOfTet> faces;
  faces.reserve(4 * mesh.tets.size());
  for (int t = 0; t < mesh.num_tets(); ++t)
    for (const auto& f : kTetFaceVertices) {
      std::array<int, 3> key{mesh.tets[t][f[0]], mesh.tets[t][f[1]], mesh.tets[t][f[2]]};
      std::sort(key.begin(), key.end());
      faces.push_back({key, t});
    }
  tbb::parallel_sort(faces.begin(), faces.end());  // a total order: the same for any thread count
  std::vector<std::array<int, 4>> neighbours(mesh.tets.size(), {-1, -1, -1, -1});  // across each face
  std::vector<char> num_neighbours(mesh.tets.size(), 0);
  std::vector<char> reached(mesh.tets.size(), 0);
  std::vector<int> stack;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1 && !region[faces[i].tet] && !reached[faces[i].tet]) {  // on the mesh's hull
      reached[faces[i].tet] = 1;
      stack.push_back(faces[i].tet);
    }
    if (j - i == 2) {
      const int a = faces[i].tet, b = faces[i + 1].tet;
      neighbours[a][num_neighbours[a]++] = b;
      neighbours[b][num_neighbours[b]++] = a;
    }
    i = j;
  }
  while (!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    for (int u : neighbours[t])
      if (u >= 0 && !region[u] && !reached[u]) reached[u] = 1, stack.push_back(u);
  }
  bool filled = false;
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (!region[t] && !reached[t]) region[t] = 1, filled = true;
  return filled;
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

namespace {

/// The vertex-connected pieces of `region` (tets sharing a vertex are in one piece), each as a
/// flag per tet, in the order of their lowest tet.
std::vector<std::vector<char>> vertex_connected_pieces(const TetMesh& mesh, const VertexIncidence& tets_around,
                                                       const std::vector<char>& region) {
  std::vector<std::vector<char>> pieces;
  std::vector<char> seen(mesh.tets.size(), 0);
  const auto in_region = [&](int t) { return region[t] != 0; };
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!region[t] || seen[t]) continue;
    pieces.emplace_back(mesh.tets.size(), 0);
    flood_through_vertices(mesh, tets_around, t, in_region, seen, pieces.back());
  }
  return pieces;
}

/// `piece` grown until its hull is a 2-manifold (the stars of offending hull vertices added, at
/// most `max_rounds` times) and, if it then encloses a cavity, with the cavity filled. A piece with
/// a tunnel (a refit zone that wraps around unflagged tets) gets up to two more rings of tets (the
/// stars of its hull vertices), which close a tunnel up to about two tets across, and the checks
/// again. False if it is still not a ball (region_is_ball).
bool grow_to_ball(const TetMesh& mesh, const VertexIncidence& tets_around, std::vector<char>& piece, int max_rounds) {
  const auto add_stars = [&](const std::vector<int>& vertices) {
    for (int v : vertices)
      for (int k = tets_around.start[v]; k < tets_around.start[v + 1]; ++k) piece[tets_around.element[k]] = 1;
  };
  constexpr int kTunnelRings = 2;
  for (int ring = 0; ring <= kTunnelRings; ++ring) {
    if (ring > 0) {
      std::vector<int> hull_vertices;
      for (const auto& f : hull_triangles(mesh, piece)) hull_vertices.insert(hull_vertices.end(), f.begin(), f.end());
      std::sort(hull_vertices.begin(), hull_vertices.end());
      hull_vertices.erase(std::unique(hull_vertices.begin(), hull_vertices.end()), hull_vertices.end());
      add_stars(hull_vertices);
    }
    bool manifold = false;
    for (int round = 0; round < max_rounds && !manifold; ++round) {
      const std::vector<int> bad = non_manifold_vertices(hull_triangles(mesh, piece));
      manifold = bad.empty();
      add_stars(bad);
    }
    if (!manifold) return false;
    if (region_is_ball(mesh, piece)) return true;
    // A piece that encloses tets of its complement (a fluid pocket inside a refit zone) has a
    // hull in several sheets; filling the pocket, whose tets CGAL keeps as they are, leaves the
    // outer sheet, which is a 2-manifold already.
    if (fill_cavities(mesh, piece) && region_is_ball(mesh, piece)) return true;
  }
  return false;
}

}  // namespace

std::vector<std::vector<char>> band_regions(const TetMesh& mesh, const std::vector<char>& band, int max_rounds) {
  const int n = mesh.num_vertices();
  const VertexIncidence tets_around = vertex_incidence(mesh);
  std::vector<char> region(mesh.tets.size(), 0);
  std::vector<char> touched(n, 0);
  for (int t = 0; t < mesh.num_tets(); ++t)
    if (band[t])
      for (int v : mesh.tets[t]) touched[v] = 1;
  for (int v = 0; v < n; ++v)
    if (touched[v])
      for (int k = tets_around.start[v]; k < tets_around.start[v + 1]; ++k) region[tets_around.element[k]] = 1;
  add_reached_solids(mesh, tets_around, region);
  // Each piece is grown to a ball on its own; pieces that grow into each other (share a vertex)
  // are merged and grown again.
  for (int merge = 0; merge < 4; ++merge) {
    std::vector<std::vector<char>> pieces = vertex_connected_pieces(mesh, tets_around, region);
    std::vector<int> owners(n, 0);
    for (std::vector<char>& piece : pieces) {
      if (!grow_to_ball(mesh, tets_around, piece, max_rounds)) return {};
      std::vector<char> used(n, 0);
      for (int t = 0; t < mesh.num_tets(); ++t)
        if (piece[t])
          for (int v : mesh.tets[t]) used[v] = 1;
      for (int v = 0; v < n; ++v) owners[v] += used[v];
    }
    if (std::all_of(owners.begin(), owners.end(), [](int k) { return k <= 1; })) return pieces;
    for (const std::vector<char>& piece : pieces)
      for (int t = 0; t < mesh.num_tets(); ++t) region[t] = region[t] || piece[t];
  }
  return {};
}

}  // namespace tetfsi::mesh
