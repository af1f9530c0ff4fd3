#pragma once
/// @file solver_detail.hpp
/// Private to the MpmSolver translation units (mpm_solver.cpp, particle_to_grid.cpp,
/// contact_momenta.cpp, grid_to_particle.cpp): the step bounds of eq. (21), the density update's
/// exponential, the prefetch of the particle passes and the loops over the box of occupied nodes.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "fluid/mpm/mpm_solver.hpp"

namespace tetfsi::mpm {
namespace detail {

constexpr int kAhead = 8;  // particle passes: prefetch the particle this many places ahead in bin order

/// Prefetches the entries of particle it[kAhead] (kAhead places ahead in bin order, usually in the
/// next cell) of the given particle arrays, if that particle exists (`end`: end of all bin ids).
template <class... Arrays>
inline void prefetch_ahead(const std::uint32_t* it, const std::uint32_t* end, const Arrays&... arrays) {
  if (end - it > kAhead) (__builtin_prefetch(&arrays[it[kAhead]]), ...);
}
constexpr std::size_t kGrain = 512;  // fixed grain of the deterministic reductions
// Below this many particles the reductions run serially (same result; see reduce.hpp).
constexpr std::size_t kSerialBelow = CellBins::kParallelMin;

/// Bound of eq. (21) for one particle, dx / (c + |v|), and the explicit viscous bound
/// rho dx^2 / (8 mu) of viscous fluids [s].
/// `p_modulus` is lambda + 2 G of a linear-elastic material (precomputed: saves the divisions of
/// Material::sound_speed in the particle loop).
inline double particle_speed(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v) {
  const double sound = mat.kind == Material::Kind::LinearElastic ? std::sqrt(p_modulus / rho)
                                                                 : mat.sound_speed(rho, -stress.trace() / 3.0);
  return sound + v.norm();
}

/// Explicit viscous bound rho dx^2 / (8 mu) [s] (infinite unless a viscous fluid).
inline double viscous_bound(const Material& mat, double rho, double dx) {
  if (mat.kind == Material::Kind::Fluid && mat.viscosity > 0) return rho * dx * dx / (8.0 * mat.viscosity);
  return std::numeric_limits<double>::infinity();
}

/// dx / c for the largest c > 0 (infinite if none): equal to the smallest dx / c_p, since rounded
/// division is monotone, with one division per step instead of one per particle.
inline double sound_bound(double c_max, double dx) {
  return c_max > 0 ? dx / c_max : std::numeric_limits<double>::infinity();
}

inline double particle_step_bound(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v,
                           double dx) {
  return std::min(sound_bound(particle_speed(mat, p_modulus, rho, stress, v), dx), viscous_bound(mat, rho, dx));
}

/// exp(x) for the density update: the Taylor polynomial to x^5 when |x| < 2^-10 (truncation below
/// x^6 / 720 < 2e-21, far under the rounding of the result; in the gas expansion h ~ 6e-5 and
/// |tr D| is of order 1), std::exp otherwise. The call to exp was ~5% of the gas expansion's
/// particle work.
inline double exp_small(double x) {
  if (std::abs(x) >= 0x1p-10) return std::exp(x);
  return 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0)))));
}


}  // namespace detail

template <class F>
void MpmSolver::for_each_box_row(F&& f) const {
  const int ny = box_hi_[1] - box_lo_[1] + 1, nz = box_hi_[2] - box_lo_[2] + 1;
  if (box_hi_[0] < box_lo_[0] || ny <= 0 || nz <= 0) return;
  auto rows = [&](int first_row, int last_row) {
    for (int row = first_row; row < last_row; ++row) {
      const int j = box_lo_[1] + row % ny, k = box_lo_[2] + row / ny;
      f(grid_.node_index(box_lo_[0], j, k), j, k);
    }
  };
  const int nx = box_hi_[0] - box_lo_[0] + 1;
  if (std::int64_t(nx) * ny * nz < 8192) return rows(0, ny * nz);  // small box: task overhead dominates
  tbb::parallel_for(tbb::blocked_range<int>(0, ny * nz, 16),
                    [&](const tbb::blocked_range<int>& r) { rows(r.begin(), r.end()); });
}

template <class F>
void MpmSolver::for_each_box_node(F&& f) const {
  const int nx = box_hi_[0] - box_lo_[0] + 1;
  for_each_box_row([&](std::int64_t first, int, int) {
    for (std::int64_t id = first; id < first + nx; ++id) f(id);
  });
}

template <class T, class Value, class Store>
void MpmSolver::gather_row(int j, int k, std::int64_t first, const T& zero, Value&& value, Store&& store) const {
  // Node (i, j, k) is corner d = (di, dj, dk) of cell (i - di, j - dj, k - dk). Per node the cells
  // come in the order (dk, dj, di) = (1, 1, 1), (1, 1, 0), (1, 0, 1), ..., (0, 0, 0). The sum of a
  // node is kept in registers and stored once (adding each cell's corner to the node arrays in
  // memory, cell row by cell row, made every addition wait for the previous store).
  const auto& lo = bins_.lo();
  const auto& hi = bins_.hi();
  std::size_t row0[4];  // first box cell of the (up to 4) cell rows around the node row
  int corner0[4];       // corner (0, dj, dk) of the node in those cells
  int rows = 0;
  for (int dk = 1; dk >= 0; --dk) {
    if (k - dk < lo[2] || k - dk > hi[2]) continue;
    for (int dj = 1; dj >= 0; --dj) {
      if (j - dj < lo[1] || j - dj > hi[1]) continue;
      row0[rows] = box_cell({lo[0], j - dj, k - dk});
      corner0[rows++] = 2 * dj + 4 * dk;
    }
  }
  const int ex = hi[0] - lo[0] + 1;  // cells per row; the row has ex + 1 nodes
  for (int i = 0; i <= ex; ++i) {
    T sum = zero;
    for (int r = 0; r < rows; ++r) {
      if (i > 0) sum += value(row0[r] + i - 1, corner0[r] + 1);  // cell i - 1, corner di = 1
      if (i < ex) sum += value(row0[r] + i, corner0[r]);          // cell i, corner di = 0
    }
    store(first + i, sum);
  }
}

}  // namespace tetfsi::mpm
