/// @file particle_to_grid.cpp
/// Steps (60)-(64) of the MPM step (trial_step): particle-to-grid mass and momentum, the velocity
/// gradient (eqs. 62, 63) and stress update (eqs. 22-26) per particle, nodal forces (eqs. 17, 18)
/// and the trial momentum (eq. 64), all in per-cell passes (cell_moments.hpp).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "fluid/mpm/mpm_solver.hpp"
#include "fluid/mpm/reduce.hpp"
#include "fluid/mpm/solver_detail.hpp"

namespace tetfsi::mpm {
using namespace detail;

bool MpmSolver::cell_gradient(const std::array<int, 3>& cell, CellGradient& G) const {
  // Inside a cell the trilinear velocity field has the bilinear gradient
  //   dv/dx (fy, fz) = [ (1-fy)(1-fz) D_00 + fy (1-fz) D_10 + (1-fy) fz D_01 + fy fz D_11 ] / dx,
  //   D_bc = v_1bc - v_0bc (nodes a b c = x, y, z offsets), and the same for y and z,
  // i.e. sum_I v_I N_I,j (eqs. 62, 63) written as a + fb b + fc c + fb fc d per column: the 8-node
  // gather of every particle becomes 36 coefficients per cell (8 particles per cell in the sphere
  // examples of section 7.1, 64 in the gas expansion of section 7.3). Computed where the cell's
  // particles need it (a separate pass over the whole box wrote and re-read 288 bytes per cell).
  const double inv = 1.0 / grid_.dx;
  const std::int64_t sx = grid_.cells[0] + 1, sxy = sx * (grid_.cells[1] + 1);
  const std::int64_t n0 = grid_.node_index(cell[0], cell[1], cell[2]);
  // v(a, b, c) = velocity of node n0 + a + b sx + c sxy.
  auto v = [&](int a, int b, int c) -> const Vec3& { return vel_[n0 + a + b * sx + c * sxy]; };
  bool open = false;
  for (int c = 0; c < 8; ++c) open = open || !(mass_[n0 + (c & 1) + ((c >> 1) & 1) * sx + (c >> 2) * sxy] > mass_eps_);
  for (int r = 0; r < 3; ++r) {
    // Column 0 (d/dx) in (fy, fz), column 1 (d/dy) in (fx, fz), column 2 (d/dz) in (fx, fy).
    const double Dx[4] = {v(1, 0, 0)[r] - v(0, 0, 0)[r], v(1, 1, 0)[r] - v(0, 1, 0)[r],
                          v(1, 0, 1)[r] - v(0, 0, 1)[r], v(1, 1, 1)[r] - v(0, 1, 1)[r]};
    const double Dy[4] = {v(0, 1, 0)[r] - v(0, 0, 0)[r], v(1, 1, 0)[r] - v(1, 0, 0)[r],
                          v(0, 1, 1)[r] - v(0, 0, 1)[r], v(1, 1, 1)[r] - v(1, 0, 1)[r]};
    const double Dz[4] = {v(0, 0, 1)[r] - v(0, 0, 0)[r], v(1, 0, 1)[r] - v(1, 0, 0)[r],
                          v(0, 1, 1)[r] - v(0, 1, 0)[r], v(1, 1, 1)[r] - v(1, 1, 0)[r]};
    const double* d[3] = {Dx, Dy, Dz};
    for (int col = 0; col < 3; ++col) {
      // d[col] = {D(0,0), D(1,0), D(0,1), D(1,1)} in the column's two fractions.
      const double* D = d[col];
      G[12 * col + r] = inv * D[0];
      G[12 * col + 3 + r] = inv * (D[1] - D[0]);
      G[12 * col + 6 + r] = inv * (D[2] - D[0]);
      G[12 * col + 9 + r] = inv * ((D[3] - D[2]) - (D[1] - D[0]));
    }
  }
  return open;
}

void MpmSolver::close_stencil(Stencil& st) const {
  // A particle on a face of its cell has N_J = 0 at the far corners J but N_J,j != 0; if such a
  // corner has no mass its velocity is undefined (v_J = 0 by convention) and its force would be
  // lost. Its velocity is taken as the particle's interpolated grid velocity sum_I N_I v_I, i.e.
  // the gradients become N~_I,j = N_I,j + N_I sum_J N_J,j on the corners with mass and 0 on the
  // empty ones. They still sum to zero (sum_I N_I = 1 over the corners with mass), so a rigid
  // translation has L = 0 and the nodal forces -V sigma N~_I,j sum to zero (momentum kept), and
  // sum_I f_I . v_I = -V sigma : L (the stress power is the grid's).
  Vec3 g_empty = Vec3::Zero();
  for (int c = 0; c < 8; ++c)
    if (!(mass_[st.node[c]] > mass_eps_)) {
      g_empty += st.dN[c];
      st.dN[c].setZero();
    }
  for (int c = 0; c < 8; ++c)
    if (mass_[st.node[c]] > mass_eps_) st.dN[c] += st.N[c] * g_empty;
}

Mat3 MpmSolver::velocity_gradient(const double f[3], const CellGradient& G) const {
  const double fx = f[0], fy = f[1], fz = f[2];
  const double pa[3] = {fy, fx, fx}, pb[3] = {fz, fz, fy};
  Mat3 L;
  for (int col = 0; col < 3; ++col) {
    const double a = pa[col], b = pb[col], ab = a * b;
    const double* g = G.data() + 12 * col;
    for (int r = 0; r < 3; ++r) L(r, col) = g[r] + a * g[3 + r] + b * g[6 + r] + ab * g[9 + r];
  }
  return L;
}


void MpmSolver::reset_nodes_outside_box(const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
  auto reset = [&](std::int64_t id) {
    mass_[id] = 0;
    for (auto* f : {&mom_old_, &mom_new_, &force_}) (*f)[id].setZero();
  };
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j) {
      const std::int64_t first = grid_.node_index(0, j, k);
      const bool row_in_box = j >= box_lo_[1] && j <= box_hi_[1] && k >= box_lo_[2] && k <= box_hi_[2];
      for (int i = lo[0]; i <= hi[0]; ++i)
        if (!row_in_box || i < box_lo_[0] || i > box_hi_[0]) reset(first + i);
    }
}

void MpmSolver::trial_step(double h) {
  if (!(h > 0) || !std::isfinite(h)) throw std::invalid_argument("MpmSolver: time step must be positive");
  auto& P = particles_;
  h_step_ = h;
  // Variable steps (section 3.2, Fig. 2): the velocities v^{n-1/2} act over the last step
  // h^{n-1/2}, and momentum advances by h^n = (h^{n-1/2} + h^{n+1/2}) / 2 (eqs. 16, 64).
  // The strain increment of eq. (62) is printed with h^n; it is taken over h^{n-1/2}, the interval
  // over which those velocities moved the particles, so that with a varying step an elastic body's
  // stress keeps following its displacement (with h^n it does not: a step pattern that lands on
  // output times, 57 steps then two shorter ones, pumped energy into the sphere-on-membrane example
  // at cell 2 mm). Equal steps give h^n = h^{n-1/2} = h, bit for bit.
  const double h_strain = h_prev_ > 0 ? h_prev_ : h;
  h_n_ = 0.5 * (h_strain + h);
  // Step 1: the grid is "rebuilt" each step. Every node of the new box gets its accumulated fields
  // (mass, p^{n-1/2}, f, p^{n+1/2}) written below, so only the nodes of the previous step's box
  // that the new box does not cover are reset (p^{n+1/2} is zero outside the box for callers). The
  // per-phase velocities vel_, dvel_, dvel_imp_ are overwritten on the whole new box before they are
  // read; impulses are non-zero only at impulse_nodes_.
  for (auto id : impulse_nodes_) impulse_[id].setZero();
  impulse_nodes_.clear();
  work_.resize(P.size());
  const auto old_lo = box_lo_, old_hi = box_hi_;
  // If the last finish_step left every particle in its cell, its bins still hold.
  if (!bins_current_ || bins_.size() != P.size()) bins_.build(grid_, P.x);
  bins_current_ = false;  // until finish_step finds every particle still in its cell
  if (bins_.empty()) {
    box_lo_ = {0, 0, 0};
    box_hi_ = {-1, -1, -1};
  } else {
    for (int a = 0; a < 3; ++a) {
      box_lo_[a] = bins_.lo()[a];
      box_hi_[a] = bins_.hi()[a] + 1;
    }
  }
  reset_nodes_outside_box(old_lo, old_hi);
  if (bins_.empty()) return;

  // Step 2a (eqs. 60, 61) in per-cell form (cell_moments.hpp): corner masses and momenta per cell,
  // then per node (eq. 51 only where contact asks for it: particle_trial_momenta).
  const auto ncell = std::size_t(bins_.hi()[0] - bins_.lo()[0] + 1) * (bins_.hi()[1] - bins_.lo()[1] + 1) *
                     (bins_.hi()[2] - bins_.lo()[2] + 1);
  cell_corners_.resize(ncell);
  const std::uint32_t* const ids_end = bins_.ids_end();
  cell_stress_bad_.resize(ncell);
  bins_.for_each_cell([&](const std::array<int, 3>& c, const std::uint32_t* b, const std::uint32_t* e) {
    CellAcc acc{};  // local: no aliasing with the particle arrays
    for (auto it = b; it != e; ++it) {
      prefetch_ahead(it, ids_end, P.x, P.v);
      double f[3];
      grid_.fractions(P.x[*it], c, f);
      add_mass_moments(f, P.mass[*it], P.v[*it], acc);
    }
    corner_masses(acc, cell_corners_[box_cell(c)]);
  });
  // Step 2b: essential conditions on p^{n-1/2}; grid velocities v_I = p_I / m_I (0 if empty).
  const int nx = box_hi_[0] - box_lo_[0] + 1;
  for_each_box_row([&](std::int64_t first, int j, int k) {
    gather_row(
        j, k, first, Eigen::Vector4d::Zero().eval(),
        [&](std::size_t cell, int corner) { return Eigen::Vector4d(cell_corners_[cell].v + 4 * corner); },
        [&](std::int64_t id, const Eigen::Vector4d& m) {
          mass_[id] = m[0];
          mom_old_[id] = m.tail<3>();
        });
    for (std::int64_t id = first; id < first + nx; ++id) {
      for (int a = 0; a < 3; ++a)
        if (mask_[id][a]) mom_old_[id][a] = 0.0;
      vel_[id] = mass_[id] > mass_eps_ ? Vec3(mom_old_[id] / mass_[id]) : Vec3::Zero();
    }
  });
  const double inv_dx = 1.0 / grid_.dx;
  // Steps 2c, 2d (eqs. 62, 63, 22, 25, 26; 17): stress update, then the particle's stress moments
  // (cell_moments.hpp), in the same pass over the cells. A cell with a corner without mass holds
  // in practice only particles on its faces (rare): their stencils are closed (close_stencil) and
  // their velocity gradients and corner forces taken from the full 8-node stencils.
  bins_.for_each_cell([&](const std::array<int, 3>& c, const std::uint32_t* b, const std::uint32_t* e) {
    const std::size_t cell = box_cell(c);
    CellAcc acc{};  // local: no aliasing with the particle arrays
    CellGradient G;
    const bool open = b != e && cell_gradient(c, G);  // an empty cell's sums are zero either way
    StressBatch bt;
    for (auto it = b; it != e; ++it) {
      const std::size_t p = *it;
      prefetch_ahead(it, ids_end, P.stress, P.rho, P.x);
      if (!open) {
        double* f = bt.f[bt.n];
        grid_.fractions(P.x[p], c, f);
        const double V = update_particle_stress(p, h_strain, velocity_gradient(f, G));
        for (int r = 0; r < 3; ++r)
          for (int col = 0; col < 3; ++col) bt.A[bt.n][r][col] = -V * P.stress[p](r, col);
        if (++bt.n == StressBatch::kBatch || it + 1 == e) {
          add_stress_moments(bt, acc);
          bt.n = 0;
        }
      } else {
        Stencil st;
        grid_.fill_stencil(P.x[p], st);
        close_stencil(st);
        Mat3 L = Mat3::Zero();  // velocity gradient L_ij = sum_I v_iI N_I,j (eqs. 62, 63)
        for (int q = 0; q < 8; ++q) L += vel_[st.node[q]] * st.dN[q].transpose();
        const double V = update_particle_stress(p, h_strain, L);
        double A[3][3];  // -V sigma of eq. (17)
        for (int r = 0; r < 3; ++r)
          for (int col = 0; col < 3; ++col) A[r][col] = -V * P.stress[p](r, col);
        add_corner_forces(st, A, acc);
      }
    }
    if (!open)
      for (auto& a : acc) a *= inv_dx;  // the 1 / dx of dN/dx (cell_moments.hpp)
    // Finiteness of the new stresses, tested here where they are in cache: a NaN or an infinity in
    // a particle's -V sigma makes every moment it enters non-finite (0 * inf is NaN too); an
    // overflow of finite terms only sends the step to check_particles, which looks again.
    double sum = 0;
    for (double a : acc) sum += a;
    cell_stress_bad_[cell] = !std::isfinite(sum);
    if (b == e)
      cell_corners_[cell] = CornerValues{};  // zeros
    else if (open)
      corner_values(acc, cell_corners_[cell]);
    else
      corner_forces(acc, cell_corners_[cell]);
  });
  // Step 2e: nodal forces (eq. 17 from the cells, eq. 18 as m_I g), grid conditions on f, trial
  // momentum p^{n+1/2} (eq. 64).
  const Vec3 g = options_.gravity;
  for_each_box_row([&](std::int64_t first, int j, int k) {
    gather_row(
        j, k, first, Vec3::Zero().eval(),
        [&](std::size_t cell, int corner) { return Vec3(cell_corners_[cell].v + 4 * corner); },
        [&](std::int64_t id, const Vec3& f) { force_[id] = f; });
    for (std::int64_t id = first; id < first + nx; ++id) {
      force_[id] += mass_[id] * g;
      for (int a = 0; a < 3; ++a)
        if (mask_[id][a]) force_[id][a] = 0.0;
      mom_new_[id] = mom_old_[id] + h_n_ * force_[id];
    }
  });
}

double MpmSolver::update_particle_stress(std::size_t p, double h, const Mat3& L) {
  auto& P = particles_;
  // Written out on the six independent components (sigma stays symmetric: it starts at zero and
  // every increment below is symmetric); the Eigen 3x3 form was a fifth of the particle work.
  // D = sym L (eq. 23) as (xx, yy, zz, xy, xz, yz); W = skew L (eq. 24) as (w01, w02, w12).
  const double d[6] = {L(0, 0), L(1, 1), L(2, 2), 0.5 * (L(0, 1) + L(1, 0)), 0.5 * (L(0, 2) + L(2, 0)),
                       0.5 * (L(1, 2) + L(2, 1))};
  const double trD = (d[0] + d[1]) + d[2];
  const auto mat_id = P.material[p];
  const auto& mat = materials_[mat_id];
  const double rho_old = P.rho[p];
  Mat3& s = P.stress[p];
  if (mat.kind == Material::Kind::LinearElastic) {
    // Mass conservation: rho^{n+1} = rho^n exp(-h tr D).
    const double rho_new = rho_old * exp_small(-h * trD);
    P.rho[p] = rho_new;
    // Hypo-elastic Jaumann update (eqs. 22, 25): sigma += h (C:D + W sigma - sigma W).
    // Eq. (22) is printed as sigma Omega + (sigma Omega)^T; with Omega_ij = (v_i,j - v_j,i)/2 as in
    // eq. (24) the objective rotation of sigma is W sigma - sigma W, which is what is used. For
    // symmetric sigma it is J = M + M^T with M = W sigma, i.e. with W = [0 a b; -a 0 c; -b -c 0]:
    //   J_xx = 2 (a s_xy + b s_xz),  J_yy = 2 (c s_yz - a s_xy),  J_zz = -2 (b s_xz + c s_yz),
    //   J_xy = a (s_yy - s_xx) + b s_yz + c s_xz,  J_xz = b (s_zz - s_xx) + a s_yz - c s_xy,
    //   J_yz = c (s_zz - s_yy) - a s_xz - b s_xy.
    const double a = 0.5 * (L(0, 1) - L(1, 0)), b = 0.5 * (L(0, 2) - L(2, 0)), c = 0.5 * (L(1, 2) - L(2, 1));
    const double sxx = s(0, 0), syy = s(1, 1), szz = s(2, 2), sxy = s(0, 1), sxz = s(0, 2), syz = s(1, 2);
    const auto& lm = lame_[mat_id];  // lambda, 2 G
    const double lam_tr = lm[0] * trD;
    const double nxx = sxx + h * ((lam_tr + lm[1] * d[0]) + 2.0 * (a * sxy + b * sxz));
    const double nyy = syy + h * ((lam_tr + lm[1] * d[1]) + 2.0 * (c * syz - a * sxy));
    const double nzz = szz + h * ((lam_tr + lm[1] * d[2]) - 2.0 * (b * sxz + c * syz));
    const double nxy = sxy + h * (lm[1] * d[3] + ((a * (syy - sxx) + b * syz) + c * sxz));
    const double nxz = sxz + h * (lm[1] * d[4] + ((b * (szz - sxx) + a * syz) - c * sxy));
    const double nyz = syz + h * (lm[1] * d[5] + ((c * (szz - syy) - a * sxz) - b * sxy));
    s(0, 0) = nxx;
    s(1, 1) = nyy;
    s(2, 2) = nzz;
    s(0, 1) = s(1, 0) = nxy;
    s(0, 2) = s(2, 0) = nxz;
    s(1, 2) = s(2, 1) = nyz;
    return P.mass[p] / rho_new;
  }
  // Fluid (eq. 26): sigma = 2 mu D' - p I, p from the EOS with the energy equation
  //   dE = (s_visc : D h) V/V0 - (p^n + p^{n+1})/2 dV/V0,
  // solved exactly for E^{n+1} because both EOS are linear in E (p = a + b E).
  // Volume ratios V/V0 = rho0/rho with V^{n+1}/V^n = exp(h tr D): one division, off the path
  // from tr D to the stress, instead of the chain of m/rho0, m/rho^n, m/rho^{n+1}, dV/V0 and the
  // EOS's rho/rho0 (that chain of dependent divisions was the critical path of the update).
  constexpr double kThird = 1.0 / 3.0;
  const double rho_new = rho_old * exp_small(-h * trD);
  P.rho[p] = rho_new;
  const double inv_rho0 = inv_rho0_[mat_id];
  const double r_old = mat.rho0 / rho_old, r_new = r_old * exp_small(h * trD);
  const double dv = r_new - r_old;
  const double mean = trD * kThird;
  const double dev[3] = {d[0] - mean, d[1] - mean, d[2] - mean};  // D' = D - tr D / 3 I
  const double dev_sq = (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2]) +
                        2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);  // D' : D'
  const double two_mu = 2.0 * mat.viscosity;
  const double w_visc = two_mu * dev_sq * h * 0.5 * (r_old + r_new);
  const double p_old = -((s(0, 0) + s(1, 1)) + s(2, 2)) * kThird;
  // Ideal gas (eq. 67): p = (gamma - 1) (rho / rho0) E, with rho / rho0 = 1 / r_new.
  const auto [pa, pb] = mat.eos == Eos::IdealGas ? std::pair<double, double>{0.0, (mat.gamma - 1.0) * (rho_new * inv_rho0)}
                                                 : mat.eos_coefficients(rho_new);
  const double E = (P.energy[p] + w_visc - 0.5 * (p_old + pa) * dv) / (1.0 + 0.5 * pb * dv);
  P.energy[p] = E;
  const double pressure = pa + pb * E;
  for (int k = 0; k < 3; ++k) s(k, k) = two_mu * dev[k] - pressure;
  s(0, 1) = s(1, 0) = two_mu * d[3];
  s(0, 2) = s(2, 0) = two_mu * d[4];
  s(1, 2) = s(2, 1) = two_mu * d[5];
  return (P.mass[p] * inv_rho0) * r_new;  // V = V0 r_new
}


}  // namespace tetfsi::mpm
