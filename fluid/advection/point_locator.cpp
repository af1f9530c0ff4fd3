#include "fluid/advection/point_locator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

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
  // About one cell per 2 tets: a few tets per cell on uniform meshes, memory O(T).
  const double cells_wanted = std::max(1.0, 0.5 * mesh.num_tets());
  const double dx = std::cbrt(ext.prod() / cells_wanted);
  for (int c = 0; c < 3; ++c) dims_[c] = std::max(1, std::min(1024, static_cast<int>(std::ceil(ext[c] / dx))));
  lo_ = lo;
  cell_size_ = ext.cwiseQuotient(dims_.cast<double>());
  const size_t ncell = static_cast<size_t>(dims_.prod());
  // Per tet, in parallel: its bounding box grown by the margin, in single precision rounded
  // outwards (it only filters grid_find's candidates, so a box a float's rounding larger tests a
  // few more tets and finds the same one; 24 instead of 48 bytes per tet). Then, serially (the
  // order within a cell decides grid_find's ties), the cells its unmargined box overlaps, counted
  // and listed as CSR.
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
  auto for_cells = [&](int t, auto&& f) {
    Eigen::Vector3d a, b;
    bounds(t, a, b);
    const Eigen::Vector3i ca = cell_of(a), cb = cell_of(b);
    for (int k = ca[2]; k <= cb[2]; ++k)
      for (int j = ca[1]; j <= cb[1]; ++j)
        for (int i = ca[0]; i <= cb[0]; ++i) f(static_cast<size_t>(i) + dims_[0] * (j + static_cast<size_t>(dims_[1]) * k));
  };
  std::vector<int> count(ncell + 1, 0);
  for (int t = 0; t < num_tets; ++t) for_cells(t, [&](size_t c) { ++count[c + 1]; });
  for (size_t c = 0; c < ncell; ++c) count[c + 1] += count[c];
  cell_start_ = count;
  cell_tets_.resize(count[ncell]);
  for (int t = 0; t < num_tets; ++t) for_cells(t, [&](size_t c) { cell_tets_[count[c]++] = t; });
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
  loc.tet = cur;
  Eigen::Vector4d l = barycentric(cur, x).cwiseMax(0.0);
  loc.bary = l / l.sum();
  loc.inside = false;
  return loc;
}

}  // namespace tetfsi::fluid
