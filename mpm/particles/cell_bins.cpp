#include "mpm/particles/cell_bins.hpp"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <limits>

namespace tetfsi::mpm {
namespace {

struct Box {
  std::array<int, 3> lo{std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
                        std::numeric_limits<int>::max()};
  std::array<int, 3> hi{std::numeric_limits<int>::min(), std::numeric_limits<int>::min(),
                        std::numeric_limits<int>::min()};
  void add(const std::array<int, 3>& c) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  }
  void add(const Box& b) {
    add(b.lo);
    add(b.hi);
  }
};

}  // namespace

void CellBins::build(const Grid& grid, const std::vector<Vec3>& x) {
  const std::size_t n = x.size();
  order_.resize(n);
  key_.resize(n);
  if (n == 0) {  // nothing to visit: for_each_cell must not walk the previous bins
    lo_ = {0, 0, 0};
    hi_ = {-1, -1, -1};
    extent_ = {0, 0, 0};
    start_.assign(1, 0);
    return;
  }
  // Box of occupied cells (min / max are exact, so the reduction order does not matter).
  // Small sets run serially (task overhead dominates; the result is the same).
  const bool parallel = n >= kParallelMin;
  auto box_of = [&](const tbb::blocked_range<std::size_t>& r, Box b) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) b.add(grid.cell_of(x[p]));
    return b;
  };
  const Box box = parallel ? tbb::parallel_reduce(tbb::blocked_range<std::size_t>(0, n, 1024), Box{}, box_of,
                                                  [](Box a, const Box& b) {
                                                    a.add(b);
                                                    return a;
                                                  })
                           : box_of(tbb::blocked_range<std::size_t>(0, n), Box{});
  lo_ = box.lo;
  hi_ = box.hi;
  // Layer axis: the longest side of the box; the other two are the fast axes of the key.
  int layer = 2;
  for (int a = 1; a >= 0; --a)
    if (hi_[a] - lo_[a] > hi_[layer] - lo_[layer]) layer = a;
  axis_ = layer == 0 ? std::array<int, 3>{1, 2, 0} : layer == 1 ? std::array<int, 3>{0, 2, 1} : std::array<int, 3>{0, 1, 2};
  for (int a = 0; a < 3; ++a) extent_[a] = hi_[axis_[a]] - lo_[axis_[a]] + 1;
  const std::size_t cells = std::size_t(extent_[0]) * extent_[1] * extent_[2];
  auto keys = [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t p = r.begin(); p != r.end(); ++p) {
      const auto c = grid.cell_of(x[p]);
      key_[p] = static_cast<std::uint32_t>(
          (c[axis_[0]] - lo_[axis_[0]]) +
          std::size_t(extent_[0]) * ((c[axis_[1]] - lo_[axis_[1]]) + std::size_t(extent_[1]) * (c[axis_[2]] - lo_[axis_[2]])));
    }
  };
  if (parallel)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), keys);
  else
    keys(tbb::blocked_range<std::size_t>(0, n));
  // Stable counting sort by key.
  start_.assign(cells + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++start_[key_[p] + 1];
  for (std::size_t k = 0; k < cells; ++k) start_[k + 1] += start_[k];
  // start_[k] is the next free slot of key k while scattering; shift back afterwards.
  for (std::size_t p = 0; p < n; ++p) order_[start_[key_[p]]++] = static_cast<std::uint32_t>(p);
  for (std::size_t k = cells; k > 0; --k) start_[k] = start_[k - 1];
  start_[0] = 0;
}

std::pair<const std::uint32_t*, const std::uint32_t*> CellBins::cell(int i, int j, int k) const {
  const std::array<int, 3> c{i, j, k};
  for (int a = 0; a < 3; ++a)
    if (c[a] < lo_[a] || c[a] > hi_[a]) return {nullptr, nullptr};
  const std::size_t key = (c[axis_[0]] - lo_[axis_[0]]) +
                          std::size_t(extent_[0]) * ((c[axis_[1]] - lo_[axis_[1]]) +
                                                     std::size_t(extent_[1]) * (c[axis_[2]] - lo_[axis_[2]]));
  return {order_.data() + start_[key], order_.data() + start_[key + 1]};
}

}  // namespace tetfsi::mpm
