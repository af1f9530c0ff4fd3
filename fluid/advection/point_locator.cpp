#include "fluid/advection/point_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "mesh/closest_point.hpp"

namespace tetfsi::fluid {
namespace {
constexpr double kInsideTolerance = 1e-10;  ///< barycentric slack for points on faces
}

PointLocator::PointLocator(const FluidMesh& mesh) : mesh_(mesh) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d hi = -lo;
  for (const auto& x : mesh.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Eigen::Vector3d ext = (hi - lo).cwiseMax(1e-12);
  // About one cell per 8 tets, memory O(T). On a graded mesh the large tets far from the solids
  // overlap several cells each: at 409k fluid tets on the flagship, one cell per 2 tets listed 6.2M
  // (tet, cell) pairs and one per 8 tets 2.9M, and the grid was built in 60 instead of 79 ms and
  // the advection took 124 instead of 139 ms (the cells the walk falls back on hold more tets,
  // which the boxes filter).
  const double cells_wanted = std::max(1.0, mesh.num_tets() / 8.0);
  const double dx = std::cbrt(ext.prod() / cells_wanted);
  for (int c = 0; c < 3; ++c) dims_[c] = std::max(1, std::min(1024, static_cast<int>(std::ceil(ext[c] / dx))));
  lo_ = lo;
  cell_size_ = ext.cwiseQuotient(dims_.cast<double>());
  const size_t ncell = static_cast<size_t>(dims_.prod());
  // Per tet, in parallel: its bounding box grown by the margin, in single precision rounded
  // outwards (it only filters grid_find's candidates, so a box a float's rounding larger tests a
  // few more tets and finds the same one; 24 instead of 48 bytes per tet). Then the cells that box
  // overlaps, listed per cell (CSR) in ascending tet order, which decides grid_find's ties.
  const int num_tets = mesh.num_tets();
  box_lo_.resize(num_tets);
  box_hi_.resize(num_tets);
  auto bounds = [&](int t, Eigen::Vector3d& a, Eigen::Vector3d& b) {
    a = b = mesh.nodes[mesh.tets[t][0]];
    for (int k = 1; k < 4; ++k) {
      a = a.cwiseMin(mesh.nodes[mesh.tets[t][k]]);
      b = b.cwiseMax(mesh.nodes[mesh.tets[t][k]]);
    }
  };
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  tbb::parallel_for(0, num_tets, [&](int t) {
    Eigen::Vector3d a, b;
    bounds(t, a, b);
    const double margin = 1e-6 * (b - a).maxCoeff();
    for (int c = 0; c < 3; ++c) {
      const double lo = a[c] - margin, hi = b[c] + margin;
      const float lo_f = static_cast<float>(lo), hi_f = static_cast<float>(hi);
      box_lo_[t][c] = lo_f > lo ? std::nextafter(lo_f, -kInfinity) : lo_f;
      box_hi_[t][c] = hi_f < hi ? std::nextafter(hi_f, kInfinity) : hi_f;
    }
  });
  // The cells a tet's (margined, float) box overlaps: a superset of those of its exact box, and
  // read from 24 bytes per tet rather than from its four nodes.
  auto for_cells = [&](int t, auto&& f) {
    const Eigen::Vector3i ca = cell_of(box_lo_[t].cast<double>()), cb = cell_of(box_hi_[t].cast<double>());
    for (int k = ca[2]; k <= cb[2]; ++k)
      for (int j = ca[1]; j <= cb[1]; ++j)
        for (int i = ca[0]; i <= cb[0]; ++i) f(static_cast<size_t>(i) + dims_[0] * (j + static_cast<size_t>(dims_[1]) * k));
  };
  // Counted and filled by up to 8 fixed ranges of tets in parallel, each range counting into its
  // own column of counts; a cell's list is then its tets of range 0, those of range 1, …, each in
  // ascending order: the lists of one serial pass, for any number of threads (the serial count and
  // fill took half the advection's time at 962k fluid tets).
  // Fewer ranges where the grid has more cells than tets (a flat domain), so that the counts stay O(T).
  const int chunks = static_cast<int>(std::clamp<size_t>(static_cast<size_t>(num_tets) / std::max<size_t>(ncell, 1), 1, 8));
  const int chunk_size = (num_tets + chunks - 1) / chunks;
  std::vector<int> offset(static_cast<size_t>(chunks) * ncell, 0);  // [chunk * ncell + cell]
  auto for_chunk = [&](int chunk, auto&& f) {
    const int end = std::min(num_tets, (chunk + 1) * chunk_size);
    for (int t = chunk * chunk_size; t < end; ++t) for_cells(t, [&](size_t c) { f(t, c); });
  };
  tbb::parallel_for(0, chunks, [&](int chunk) {
    int* count = offset.data() + static_cast<size_t>(chunk) * ncell;
    for_chunk(chunk, [&](int, size_t c) { ++count[c]; });
  });
  cell_start_.resize(ncell + 1);
  int next = 0;
  for (size_t c = 0; c < ncell; ++c) {
    cell_start_[c] = next;
    for (int chunk = 0; chunk < chunks; ++chunk) {
      int& o = offset[static_cast<size_t>(chunk) * ncell + c];
      const int count = o;
      o = next;
      next += count;
    }
  }
  cell_start_[ncell] = next;
  cell_tets_.resize(next);
  tbb::parallel_for(0, chunks, [&](int chunk) {
    int* cursor = offset.data() + static_cast<size_t>(chunk) * ncell;
    for_chunk(chunk, [&](int t, size_t c) { cell_tets_[cursor[c]++] = t; });
  });
}

Eigen::Vector3i PointLocator::cell_of(const Eigen::Vector3d& x) const {
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(static_cast<int>(std::floor((x[a] - lo_[a]) / cell_size_[a])), 0, dims_[a] - 1);
  return c;
}

Eigen::Vector4d PointLocator::barycentric(int t, const Eigen::Vector3d& x) const {
  // lambda_k(x) = lambda_k(centroid) + grad(phi_k).(x - centroid), lambda_k(centroid) = 1/4.
  const Eigen::Vector3d d = x - mesh_.centroid(t);
  Eigen::Vector4d l;
  for (int k = 0; k < 4; ++k) l[k] = 0.25 + mesh_.grad[t][k].dot(d);
  return l;
}

int PointLocator::grid_find(const Eigen::Vector3d& x) const {
  for (int a = 0; a < 3; ++a)
    if (x[a] < lo_[a] - 1e-9 * cell_size_[a] || x[a] > lo_[a] + dims_[a] * cell_size_[a] * (1 + 1e-12) + 1e-9 * cell_size_[a])
      return -1;
  const Eigen::Vector3i c = cell_of(x);
  const size_t ci = static_cast<size_t>(c[0]) + dims_[0] * (c[1] + static_cast<size_t>(dims_[1]) * c[2]);
  int best = -1;
  double best_min = -kInsideTolerance;
  for (int i = cell_start_[ci]; i < cell_start_[ci + 1]; ++i) {
    const int t = cell_tets_[i];
    if ((x.array() < box_lo_[t].cast<double>().array()).any() || (x.array() > box_hi_[t].cast<double>().array()).any())
      continue;
    const double m = barycentric(t, x).minCoeff();
    if (m >= best_min) {  // the tet that contains x most robustly
      best_min = m;
      best = cell_tets_[i];
    }
  }
  return best;
}

int PointLocator::grid_nearest_tet(const Eigen::Vector3d& x) const {
  const Eigen::Vector3i c = cell_of(x);
  const int rmax = dims_.maxCoeff();
  for (int r = 0; r <= rmax; ++r)  // rings of growing radius; the first non-empty cell wins
    for (int k = std::max(0, c[2] - r); k <= std::min(dims_[2] - 1, c[2] + r); ++k)
      for (int j = std::max(0, c[1] - r); j <= std::min(dims_[1] - 1, c[1] + r); ++j)
        for (int i = std::max(0, c[0] - r); i <= std::min(dims_[0] - 1, c[0] + r); ++i) {
          const size_t ci = static_cast<size_t>(i) + dims_[0] * (j + static_cast<size_t>(dims_[1]) * k);
          if (cell_start_[ci + 1] > cell_start_[ci]) return cell_tets_[cell_start_[ci]];
        }
  return 0;
}

Location PointLocator::locate(const Eigen::Vector3d& x, int hint) const {
  Location loc;
  int cur = hint;
  if (cur < 0 || cur >= mesh_.num_tets()) {
    const int t = grid_find(x);
    if (t >= 0) {
      loc.tet = t;
      loc.bary = barycentric(t, x);
      loc.inside = true;
      return loc;
    }
    cur = grid_nearest_tet(x);
  }
  const int max_steps = 200;
  bool hit_boundary = false;
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::Vector4d l = barycentric(cur, x);
    if (l.minCoeff() >= -kInsideTolerance) {
      loc.tet = cur;
      loc.bary = l;
      loc.inside = true;
      return loc;
    }
    // Cross the face with the most negative coordinate that has a fluid neighbour.
    int next = -1;
    double most = 0.0;
    for (int k = 0; k < 4; ++k)
      if (l[k] < -kInsideTolerance && mesh_.neighbor[cur][k] >= 0 && l[k] < most) {
        most = l[k];
        next = mesh_.neighbor[cur][k];
      }
    const int kmin = static_cast<int>(std::min_element(l.data(), l.data() + 4) - l.data());
    if (mesh_.neighbor[cur][kmin] < 0) hit_boundary = true;
    if (next < 0 || hit_boundary) break;
    cur = next;
  }
  // Walk stuck or blocked by the boundary: the grid decides.
  const int t = grid_find(x);
  if (t >= 0) {
    loc.tet = t;
    loc.bary = barycentric(t, x);
    loc.inside = true;
    return loc;
  }
  return nearest_on_boundary(x);
}

Location PointLocator::nearest_on_boundary(const Eigen::Vector3d& x) const {
  // Blocks of (2r + 1)^3 cells around the cell of p, x projected onto the grid's box. A face not
  // yet seen lies in a cell outside the block, hence at least as far from x as p is from the
  // block's sides that have cells beyond them (projecting onto a box moves no point nearer to a
  // point of the box): the search stops once that exceeds the nearest face found.
  const Eigen::Vector3d hi = lo_ + cell_size_.cwiseProduct(dims_.cast<double>());
  const Eigen::Vector3d p = x.cwiseMax(lo_).cwiseMin(hi);
  const Eigen::Vector3i c = cell_of(x);
  double best2 = std::numeric_limits<double>::infinity();
  int best_tet = -1;
  Eigen::Vector3d best_point = x;
  auto visit = [&](size_t cell) {
    for (int n = cell_start_[cell]; n < cell_start_[cell + 1]; ++n) {
      const int t = cell_tets_[n];
      const auto& tet = mesh_.tets[t];
      for (int f = 0; f < 4; ++f) {
        if (mesh_.neighbor[t][f] >= 0) continue;  // boundary faces only
        const mesh::ClosestPoint q = mesh::closest_point_on_triangle(
            x, mesh_.nodes[tet[(f + 1) % 4]], mesh_.nodes[tet[(f + 2) % 4]], mesh_.nodes[tet[(f + 3) % 4]]);
        if (q.distance * q.distance < best2) {
          best2 = q.distance * q.distance;
          best_tet = t;
          best_point = q.point;
        }
      }
    }
  };
  const int rmax = dims_.maxCoeff();
  for (int r = 0; r <= rmax; ++r) {
    for (int k = std::max(0, c[2] - r); k <= std::min(dims_[2] - 1, c[2] + r); ++k)
      for (int j = std::max(0, c[1] - r); j <= std::min(dims_[1] - 1, c[1] + r); ++j)
        for (int i = std::max(0, c[0] - r); i <= std::min(dims_[0] - 1, c[0] + r); ++i)
          if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) == r)  // this ring only
            visit(static_cast<size_t>(i) + dims_[0] * (j + static_cast<size_t>(dims_[1]) * k));
    double unseen = std::numeric_limits<double>::infinity();  // distance from p to the cells beyond the block
    for (int a = 0; a < 3; ++a) {
      if (c[a] - r > 0) unseen = std::min(unseen, p[a] - (lo_[a] + (c[a] - r) * cell_size_[a]));
      if (c[a] + r < dims_[a] - 1) unseen = std::min(unseen, lo_[a] + (c[a] + r + 1) * cell_size_[a] - p[a]);
    }
    if (best_tet >= 0 && unseen * unseen >= best2) break;
  }
  Location loc;
  loc.inside = false;
  loc.tet = best_tet;
  if (best_tet < 0) {  // no boundary face at all (no mesh of finite extent): some tet, its centroid
    loc.tet = grid_nearest_tet(x);
    return loc;
  }
  const Eigen::Vector4d l = barycentric(best_tet, best_point).cwiseMax(0.0);
  loc.bary = l / l.sum();
  return loc;
}

}  // namespace tetfsi::fluid
