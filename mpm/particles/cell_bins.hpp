#pragma once
/// @file cell_bins.hpp
/// Particles bucketed by background-grid cell (rebuilt by the solver whenever a particle changed
/// cell), for
///  - the particle passes in per-cell form (cell_moments.hpp): each cell's particles, in bin order,
///    write only to that cell's accumulators, so cells run in parallel (layers along the longest
///    axis of the box) without races or atomics, and every sum has one order whatever the number
///    of threads (bit-identical results);
///  - neighbour queries (the particles of the cells around a grid node, for contact);
///  - the box of occupied cells, so that node loops cover only that box.
/// A counting sort (stable, O(particles + cells of the box)) is used rather than a comparison
/// sort; the particle arrays themselves are not reordered (particle ids stay stable for probes).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "mpm/particles/grid.hpp"

namespace tetfsi::mpm {

class CellBins {
 public:
  /// Below this many particles the cell passes run serially (task overhead dominates; the
  /// result is the same either way). With the per-cell passes (one fork-join per pass, no
  /// colouring) two threads already pay off for the gas expansion's 2,736 particles: to t = 0.5,
  /// medians of 5 interleaved runs 3.59 s on two threads against 4.55 s on one (the coloured
  /// passes had gained 7% at a threshold of 2,048, so it was 16,384 before).
  static constexpr std::size_t kParallelMin = 1024;

  /// Bins the positions `x` (all inside `grid`). The layer axis is the axis along which the box of
  /// occupied cells is longest (ties: the later axis).
  void build(const Grid& grid, const std::vector<Vec3>& x);

  /// Box of occupied cells, inclusive: cells lo()[a] ..= hi()[a] on axis a (valid after build with
  /// at least one particle).
  const std::array<int, 3>& lo() const { return lo_; }
  const std::array<int, 3>& hi() const { return hi_; }
  bool empty() const { return order_.empty(); }
  /// End of the particle ids of all cells (the ranges passed by for_each_cell lie in one array, in
  /// visiting order within a layer; for prefetching the particles a few places ahead).
  const std::uint32_t* ids_end() const { return order_.data() + order_.size(); }
  /// Number of particles binned by the last build.
  std::size_t size() const { return order_.size(); }

  /// Particle ids of cell (i, j, k) (global cell indices) as a [begin, end) pointer range; empty
  /// outside the box.
  std::pair<const std::uint32_t*, const std::uint32_t*> cell(int i, int j, int k) const;


  /// Calls f(cell, begin, end) for every cell of the box (global (i, j, k); its particle ids as a
  /// [begin, end) pointer range in bin order, possibly empty), cells of one layer along the layer
  /// axis in key order, layers in parallel (serially below kParallelMin particles). f may write
  /// only data of its own cell; the result then does not depend on the number of threads.
  template <class F>
  void for_each_cell(F&& f) const {
    if (order_.empty()) return;
    auto layers = [&](int first, int last) {
      std::array<int, 3> c;
      for (int l = first; l < last; ++l) {
        c[axis_[2]] = lo_[axis_[2]] + l;
        std::size_t key = std::size_t(l) * extent_[0] * extent_[1];
        for (int b = 0; b < extent_[1]; ++b) {
          c[axis_[1]] = lo_[axis_[1]] + b;
          for (int a = 0; a < extent_[0]; ++a, ++key) {
            c[axis_[0]] = lo_[axis_[0]] + a;
            f(c, order_.data() + start_[key], order_.data() + start_[key + 1]);
          }
        }
      }
    };
    if (order_.size() < kParallelMin) return layers(0, extent_[2]);
    tbb::parallel_for(tbb::blocked_range<int>(0, extent_[2], 1),
                      [&](const tbb::blocked_range<int>& r) { layers(r.begin(), r.end()); });
  }

 private:
  std::array<int, 3> lo_{0, 0, 0}, hi_{-1, -1, -1};
  /// Axes of the local key, fastest first: axis_[2] is the layer axis.
  std::array<int, 3> axis_{0, 1, 2};
  std::array<int, 3> extent_{0, 0, 0};  ///< cells of the box along axis_[0], axis_[1], axis_[2]
  std::vector<std::uint32_t> key_;    ///< local cell key per particle
  std::vector<std::uint32_t> start_;  ///< start_[key] .. start_[key + 1]: positions in order_
  std::vector<std::uint32_t> order_;  ///< particle ids sorted by key (stable)
};

}  // namespace tetfsi::mpm
