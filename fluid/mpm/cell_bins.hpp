#pragma once
/// @file cell_bins.hpp
/// Particles bucketed by background-grid cell, rebuilt every step, for
///  - the parallel particle-to-grid scatter without races or atomics: a particle in cell c writes
///    only to the 8 nodes of c, so particles in slabs of two cell layers along one axis that are
///    two slabs apart never write to the same node. Even slabs run in parallel, then odd slabs;
///    each slab is one task that visits its particles in bin order. Every node therefore receives
///    its contributions in the same order whatever the number of threads (bit-identical sums);
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

#include "fluid/mpm/grid.hpp"

namespace tetfsi::mpm {

class CellBins {
 public:
  /// Below this many particles the coloured passes run serially (task overhead dominates; the
  /// result is the same either way).
  static constexpr std::size_t kParallelMin = 16384;

  /// Bins the positions `x` (all inside `grid`). The slab axis is the axis along which the box of
  /// occupied cells is longest (ties: the later axis).
  void build(const Grid& grid, const std::vector<Vec3>& x);

  /// Box of occupied cells, inclusive: cells lo()[a] ..= hi()[a] on axis a (valid after build with
  /// at least one particle).
  const std::array<int, 3>& lo() const { return lo_; }
  const std::array<int, 3>& hi() const { return hi_; }
  bool empty() const { return order_.empty(); }

  /// Particle ids of cell (i, j, k) (global cell indices) as a [begin, end) pointer range; empty
  /// outside the box.
  std::pair<const std::uint32_t*, const std::uint32_t*> cell(int i, int j, int k) const;

  /// Position of a particle id in the binned order, from a pointer of a cell() range.
  std::size_t position(const std::uint32_t* it) const { return static_cast<std::size_t>(it - order_.data()); }
  /// Particle ids in binned order (position q holds order()[q]).
  const std::vector<std::uint32_t>& order() const { return order_; }

  /// Calls f(q, p) for every particle p at binned position q; concurrent calls never write to the
  /// same grid node through the particle's own 8-node stencil (see the file comment). Deterministic
  /// order per node.
  template <class F>
  void for_each_coloured(F&& f) const {
    const int slabs = (extent_[2] + 1) / 2;  // slabs of two layers along the slab axis
    for (int colour = 0; colour < 2; ++colour) {
      const int count = (slabs - colour + 1) / 2;
      if (count <= 0) continue;
      if (order_.size() < kParallelMin) {  // same per-node order as the parallel branch
        for (int s = 0; s < count; ++s) {
          const auto [b, e] = slab_range(2 * s + colour);
          for (std::uint32_t q = b; q < e; ++q) f(std::size_t(q), static_cast<std::size_t>(order_[q]));
        }
        continue;
      }
      tbb::parallel_for(tbb::blocked_range<int>(0, count, 1),
                        [&](const tbb::blocked_range<int>& r) {
                          for (int s = r.begin(); s != r.end(); ++s) {
                            const int slab = 2 * s + colour;
                            const auto [b, e] = slab_range(slab);
                            for (std::uint32_t q = b; q < e; ++q) f(std::size_t(q), static_cast<std::size_t>(order_[q]));
                          }
                        },
                        tbb::simple_partitioner());
    }
  }

 private:
  /// [begin, end) positions in order_ of slab `slab` (two layers along the slab axis).
  std::pair<std::uint32_t, std::uint32_t> slab_range(int slab) const;

  std::array<int, 3> lo_{0, 0, 0}, hi_{-1, -1, -1};
  /// Axes of the local key, fastest first: axis_[2] is the slab axis.
  std::array<int, 3> axis_{0, 1, 2};
  std::array<int, 3> extent_{0, 0, 0};  ///< cells of the box along axis_[0], axis_[1], axis_[2]
  std::vector<std::uint32_t> key_;    ///< local cell key per particle
  std::vector<std::uint32_t> start_;  ///< start_[key] .. start_[key + 1]: positions in order_
  std::vector<std::uint32_t> order_;  ///< particle ids sorted by key (stable)
};

}  // namespace tetfsi::mpm
