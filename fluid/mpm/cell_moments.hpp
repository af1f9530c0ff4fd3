#pragma once
/// @file cell_moments.hpp
/// Per-cell form of the particle-to-grid sums of the explicit MPM (Lian, Liu & Zhang 2014):
/// particles add to the 36 accumulators of their own cell (no scattered writes to 8 nodes), and
/// each node then sums the corner values of its (up to 8) cells in a fixed order.
///
/// With the in-cell position f = (x - x_cell) / dx and the 1D hats w_0(f) = 1 - f, w_1(f) = f, the
/// trilinear function of corner d = (di, dj, dk) is N_d = w_di(fx) w_dj(fy) w_dk(fz), and
///   dN_d/dx = s_di w_dj(fy) w_dk(fz) / dx,  s_0 = -1, s_1 = +1  (and alike for y, z),
/// i.e. the x-derivative is a bilinear function of (fy, fz) written in the corner basis of that
/// face. Hence, per cell (sums over its particles p):
///  - mass and momentum, eqs. (60), (61): the corner values m_d = sum_p m_p N_d and
///    P_d = sum_p m_p v_p N_d (32 accumulators, 32 FMAs per particle);
///  - internal forces, eq. (17), f_I = -sum_p V_p sigma_p grad N_I: with A_p = -V_p sigma_p,
///    S^x_(dj,dk) = sum_p A_p[:, 0] w_dj w_dk, S^y_(di,dk) = sum_p A_p[:, 1] w_di w_dk,
///    S^z_(di,dj) = sum_p A_p[:, 2] w_di w_dj (36 accumulators, 36 FMAs per particle), and corner d
///    receives (s_di S^x_(dj,dk) + s_dj S^y_(di,dk) + s_dk S^z_(di,dj)) / dx.
/// The body force of eq. (18), sum_p N_I m_p g = m_I g, is added per node.
/// The corner basis (rather than monomials 1, f, ...) keeps a node that only a cell's far side
/// reaches free of cancellation: every accumulated term is non-negative for the masses.
#include <array>
#include <cstdint>

#include "fluid/mpm/grid.hpp"

namespace tetfsi::mpm {

using CellAcc = std::array<double, 36>;

/// Corners c = di + 2 dj + 4 dk of a cell, as in Stencil. The layouts below keep the values that
/// one particle scales by the same factor contiguous, so that the sums vectorise.
/// N_c = w_dx(fx) w_dy(fy) w_dz(fz) of the 8 corners (the values of Grid::fill_stencil).
inline void corner_weights(const double f[3], double N[8]) {
  // (w_dx w_dy) w_dz with the four products w_dx w_dy shared (12 products instead of 16).
  const double wx0 = 1.0 - f[0], wx1 = f[0], wy0 = 1.0 - f[1], wy1 = f[1], wz0 = 1.0 - f[2], wz1 = f[2];
  const double b00 = wx0 * wy0, b10 = wx1 * wy0, b01 = wx0 * wy1, b11 = wx1 * wy1;
  N[0] = b00 * wz0;
  N[1] = b10 * wz0;
  N[2] = b01 * wz0;
  N[3] = b11 * wz0;
  N[4] = b00 * wz1;
  N[5] = b10 * wz1;
  N[6] = b01 * wz1;
  N[7] = b11 * wz1;
}

/// grad N_c of corner c (the value of Grid::fill_stencil), inv_dx = 1 / dx.
inline Vec3 corner_gradient(const double f[3], int c, double inv_dx) {
  const int di = c & 1, dj = (c >> 1) & 1, dk = c >> 2;
  const double w[3] = {di ? f[0] : 1.0 - f[0], dj ? f[1] : 1.0 - f[1], dk ? f[2] : 1.0 - f[2]};
  const double g[3] = {di ? inv_dx : -inv_dx, dj ? inv_dx : -inv_dx, dk ? inv_dx : -inv_dx};
  return Vec3(g[0] * w[1] * w[2], w[0] * g[1] * w[2], w[0] * w[1] * g[2]);
}

/// The 8 node ids of cell (i, j, k), corner order c = di + 2 dj + 4 dk.
inline void corner_nodes(const Grid& grid, const std::array<int, 3>& cell, std::int64_t id[8]) {
  const std::int64_t sx = grid.cells[0] + 1, sxy = sx * (grid.cells[1] + 1);
  const std::int64_t n0 = grid.node_index(cell[0], cell[1], cell[2]);
  for (int c = 0; c < 8; ++c) id[c] = n0 + (c & 1) + ((c >> 1) & 1) * sx + (c >> 2) * sxy;
}

/// Adds m N_c and m v N_c of one particle (in-cell position f) to a cell's mass moments:
/// acc[c] = m_c, acc[8 (1 + r) + c] = P_c,r.
inline void add_mass_moments(const double f[3], double m, const Vec3& v, CellAcc& acc) {
  double N[8];
  corner_weights(f, N);
  const double mv[4] = {m, m * v[0], m * v[1], m * v[2]};
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 8; ++c) acc[8 * k + c] += mv[k] * N[c];
}

/// Up to kBatch particles of one cell: in-cell positions f and A = -V sigma.
struct StressBatch {
  static constexpr int kBatch = 16;
  int n = 0;
  double f[kBatch][3];
  double A[kBatch][3][3];
};

/// Adds the stress moments S^x, S^y, S^z of a batch (particles in batch order):
/// acc[12 j + 4 r + e] = S^j_e,r with e = b + 2 c the corner (b, c) of the face of column j.
/// Column by column, so that the 12 sums of a column stay in registers.
inline void add_stress_moments(const StressBatch& bt, CellAcc& acc) {
  for (int j = 0; j < 3; ++j) {
    const int ia = j == 0 ? 1 : 0, ib = j == 2 ? 1 : 2;  // the two other axes: (y, z), (x, z), (x, y)
    double s[12];
    for (int i = 0; i < 12; ++i) s[i] = acc[12 * j + i];
    for (int k = 0; k < bt.n; ++k) {
      const double a = bt.f[k][ia], b = bt.f[k][ib];
      const double W[4] = {(1.0 - a) * (1.0 - b), a * (1.0 - b), (1.0 - a) * b, a * b};
      for (int r = 0; r < 3; ++r)
        for (int e = 0; e < 4; ++e) s[4 * r + e] += bt.A[k][r][j] * W[e];
    }
    for (int i = 0; i < 12; ++i) acc[12 * j + i] = s[i];
  }
}

/// Adds the forces A dN_c of a particle with an explicit (e.g. closed) stencil to a cell's corner
/// forces acc[3 c + r] (the accumulators of a cell whose particles all take this path).
inline void add_corner_forces(const Stencil& st, const double A[3][3], CellAcc& acc) {
  for (int c = 0; c < 8; ++c)
    for (int r = 0; r < 3; ++r) acc[3 * c + r] += (A[r][0] * st.dN[c][0] + A[r][1] * st.dN[c][1]) + A[r][2] * st.dN[c][2];
}

/// Force on corner c = di + 2 dj + 4 dk from a cell's stress moments (the solver has multiplied
/// them by 1 / dx once per cell).
inline Vec3 corner_force_moment(const CellAcc& acc, int c) {
  const int di = c & 1, dj = (c >> 1) & 1, dk = c >> 2;
  const double* sx = acc.data() + dj + 2 * dk;
  const double* sy = acc.data() + 12 + di + 2 * dk;
  const double* sz = acc.data() + 24 + di + 2 * dj;
  Vec3 f;
  for (int r = 0; r < 3; ++r)
    f[r] = (di ? sx[4 * r] : -sx[4 * r]) + (dj ? sy[4 * r] : -sy[4 * r]) + (dk ? sz[4 * r] : -sz[4 * r]);
  return f;
}

/// A cell's sums as its corner nodes read them: the (up to) 4 values of corner c at [4 c, 4 c + 4),
/// one 32-byte block, so that a node gathering its 8 cells reads 8 blocks (the accumulator
/// layouts above spread one corner's values over the whole cell).
struct alignas(64) CornerValues {
  double v[32];
};

/// Corner c's (m_c, P_c) from the mass moments acc[8 k + c] of add_mass_moments.
inline void corner_masses(const CellAcc& acc, CornerValues& out) {
  for (int c = 0; c < 8; ++c)
    for (int k = 0; k < 4; ++k) out.v[4 * c + k] = acc[8 * k + c];
}

/// Corner c's force (and a zero) from the stress moments acc (scaled by 1 / dx; corner_force_moment).
inline void corner_forces(const CellAcc& acc, CornerValues& out) {
#pragma GCC unroll 8
  for (int c = 0; c < 8; ++c) {
    const Vec3 f = corner_force_moment(acc, c);
    for (int r = 0; r < 3; ++r) out.v[4 * c + r] = f[r];
    out.v[4 * c + 3] = 0.0;
  }
}

/// Corner c's force (and a zero) from the per-corner forces acc[3 c + r] of add_corner_forces.
inline void corner_values(const CellAcc& acc, CornerValues& out) {
  for (int c = 0; c < 8; ++c) {
    for (int r = 0; r < 3; ++r) out.v[4 * c + r] = acc[3 * c + r];
    out.v[4 * c + 3] = 0.0;
  }
}

}  // namespace tetfsi::mpm
