#pragma once
/// @file grid.hpp
/// Regular background grid of the material point method (Lian, Liu & Zhang 2014, section 3).
///
/// Layout choice: a dense box of (nx+1)(ny+1)(nz+1) nodes covering the whole computational domain,
/// rebuilt (zeroed) every step (section 6, steps 1 and 6). Dense storage keeps the particle-to-grid
/// scatter a plain indexed add and the node loops trivially parallel; the paper's examples fit a
/// box of at most a few 10^5 nodes. Shape functions are trilinear (8 nodes per particle).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace tetfsi::mpm {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Boundary condition on one face of the grid box, applied to grid nodal momentum and force
/// (section 6, steps 2b and 2e: "if node I is fixed in direction i, set p_iI = 0, f_iI = 0").
enum class FaceBc : std::uint8_t {
  Free,   ///< nothing imposed
  Slip,   ///< normal component zero (symmetry plane or frictionless wall)
  Fixed,  ///< all components zero
};

/// Shape-function data of one point: the 8 nodes of its cell, weights N_I and gradients N_I,j.
/// Left uninitialised by default (Grid::fill_stencil writes every field): loops that build one per
/// particle (the closed-stencil path, the membrane nodes of the contact) need no zeroing.
struct Stencil {
  std::array<std::int64_t, 8> node;
  std::array<double, 8> N;
  std::array<Vec3, 8> dN;
};

/// The regular grid: origin `lo`, cubic cell size `dx` [m], `cells` cells per axis.
struct Grid {
  Vec3 lo = Vec3::Zero();
  double dx = 1.0;
  std::array<int, 3> cells{1, 1, 1};
  /// Face conditions, order x-lo, x-hi, y-lo, y-hi, z-lo, z-hi.
  std::array<FaceBc, 6> faces{FaceBc::Free, FaceBc::Free, FaceBc::Free,
                              FaceBc::Free, FaceBc::Free, FaceBc::Free};
  /// Axes on which the motion is suppressed everywhere (1D: {false,true,true}; plane strain in
  /// x-y: {false,false,true}). Implemented as a zero momentum/force component on every node.
  std::array<bool, 3> constrained_axes{false, false, false};

  /// Builds a grid covering [lo, hi] with cells of size dx (the upper bound is rounded up).
  /// @throws std::invalid_argument if dx <= 0 or hi <= lo on some axis
  static Grid covering(const Vec3& lo, const Vec3& hi, double dx);

  Vec3 hi() const { return lo + dx * Vec3(cells[0], cells[1], cells[2]); }
  std::int64_t num_nodes() const {
    return std::int64_t(cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1);
  }
  std::int64_t node_index(int i, int j, int k) const {
    return i + std::int64_t(cells[0] + 1) * (j + std::int64_t(cells[1] + 1) * k);
  }
  Vec3 node_position(std::int64_t id) const;
  /// True if x lies inside the grid box (closed at the low end, open at the high end).
  bool contains(const Vec3& x) const { return contains(x, 1.0 / dx); }
  /// contains() with inv_dx = 1 / dx given (hoisted out of particle loops); false for a non-finite x.
  bool contains(const Vec3& x, double inv_dx) const {
    for (int a = 0; a < 3; ++a) {
      const double s = (x[a] - lo[a]) * inv_dx;  // the same scaling as stencil() and cell_of()
      if (!(s >= 0.0) || !(s < cells[a])) return false;
    }
    return true;
  }
  /// Trilinear shape functions of the cell containing x (eq. 15 uses N_Ip; eq. 17 uses N_Ip,j).
  /// @throws std::out_of_range if x is outside the grid
  Stencil stencil(const Vec3& x) const;
  /// The same without the range check, for the particle loops (x must lie inside the grid).
  Stencil stencil_unchecked(const Vec3& x) const {
    Stencil st;
    fill_stencil(x, st);
    return st;
  }
  /// stencil_unchecked written straight into `st` (no temporary to copy in the particle loops).
  void fill_stencil(const Vec3& x, Stencil& st) const {
    int base[3];
    double f[3];
    const double inv = 1.0 / dx;
    for (int a = 0; a < 3; ++a) {
      const double s = (x[a] - lo[a]) * inv;
      base[a] = static_cast<int>(s);
      f[a] = s - base[a];
    }
    const std::int64_t sx = cells[0] + 1, sxy = sx * (cells[1] + 1);
    const std::int64_t b = node_index(base[0], base[1], base[2]);
    // 1D linear hat functions and their derivatives along each axis.
    const double w[3][2] = {{1.0 - f[0], f[0]}, {1.0 - f[1], f[1]}, {1.0 - f[2], f[2]}};
    const double g[2] = {-inv, inv};
    int c = 0;
    for (int dk = 0; dk < 2; ++dk)
      for (int dj = 0; dj < 2; ++dj)
        for (int di = 0; di < 2; ++di, ++c) {
          st.node[c] = b + di + dj * sx + dk * sxy;
          st.N[c] = w[0][di] * w[1][dj] * w[2][dk];
          st.dN[c] = Vec3(g[di] * w[1][dj] * w[2][dk], w[0][di] * g[dj] * w[2][dk], w[0][di] * w[1][dj] * g[dk]);
        }
  }
  /// Position of x in its cell `cell` (= cell_of(x)), f = (x - x_cell) / dx in [0, 1), computed
  /// as in fill_stencil (the same values).
  void fractions(const Vec3& x, const std::array<int, 3>& cell, double f[3]) const {
    const double inv = 1.0 / dx;
    for (int a = 0; a < 3; ++a) f[a] = (x[a] - lo[a]) * inv - cell[a];
  }
  /// Index (i, j, k) of the cell containing x, as used by stencil() (x inside the grid).
  std::array<int, 3> cell_of(const Vec3& x) const {
    const double inv = 1.0 / dx;
    return {static_cast<int>((x[0] - lo[0]) * inv), static_cast<int>((x[1] - lo[1]) * inv),
            static_cast<int>((x[2] - lo[2]) * inv)};
  }
  /// Per-node mask of components held at zero by faces and constrained axes (3 bools per node).
  std::vector<std::array<bool, 3>> build_constraint_mask() const;
};

}  // namespace tetfsi::mpm
