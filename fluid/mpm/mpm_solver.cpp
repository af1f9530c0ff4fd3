#include "fluid/mpm/mpm_solver.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fluid/mpm/reduce.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tetfsi::mpm {
namespace {

constexpr std::size_t kGrain = 512;  // fixed grain of the deterministic reductions
// Below this many particles the reductions run serially (same result; see reduce.hpp).
constexpr std::size_t kSerialBelow = CellBins::kParallelMin;

/// Bound of eq. (21) for one particle, h / (c + |v|), and the explicit viscous bound
/// rho h^2 / (8 mu) of viscous fluids [s].
/// `p_modulus` is lambda + 2 G of a linear-elastic material (precomputed: saves the divisions of
/// Material::sound_speed in the particle loop).
double particle_speed(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v) {
  const double sound = mat.kind == Material::Kind::LinearElastic ? std::sqrt(p_modulus / rho)
                                                                 : mat.sound_speed(rho, -stress.trace() / 3.0);
  return sound + v.norm();
}

/// Explicit viscous bound rho h^2 / (8 mu) [s] (infinite unless a viscous fluid).
double viscous_bound(const Material& mat, double rho, double h) {
  if (mat.kind == Material::Kind::Fluid && mat.viscosity > 0) return rho * h * h / (8.0 * mat.viscosity);
  return std::numeric_limits<double>::infinity();
}

/// h / c for the largest c > 0 (infinite if none): equal to the smallest h / c_p, since rounded
/// division is monotone, with one division per step instead of one per particle.
double sound_bound(double c_max, double h) {
  return c_max > 0 ? h / c_max : std::numeric_limits<double>::infinity();
}

double particle_step_bound(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v,
                           double h) {
  return std::min(sound_bound(particle_speed(mat, p_modulus, rho, stress, v), h), viscous_bound(mat, rho, h));
}

/// exp(x) for the density update: the Taylor polynomial to x^5 when |x| < 2^-10 (truncation below
/// x^6 / 720 < 2e-21, far under the rounding of the result; in the gas expansion dt ~ 6e-5 and
/// |tr D| is of order 1), std::exp otherwise. The call to exp was ~5% of the gas expansion's
/// particle work.
double exp_small(double x) {
  if (std::abs(x) >= 0x1p-10) return std::exp(x);
  return 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0)))));
}

}  // namespace

void MpmSolver::cell_gradients() {
  // Inside a cell the trilinear velocity field has the bilinear gradient
  //   dv/dx (fy, fz) = [ (1-fy)(1-fz) D_00 + fy (1-fz) D_10 + (1-fy) fz D_01 + fy fz D_11 ] / h,
  //   D_bc = v_1bc - v_0bc (nodes a b c = x, y, z offsets), and the same for y and z,
  // i.e. sum_I v_I N_I,j (eqs. 62, 63) written as a + fb b + fc c + fb fc d per column: the 8-node
  // gather of every particle becomes 36 coefficients per cell (64 particles per cell in the gas
  // expansion of section 7.3).
  const auto& lo = bins_.lo();
  const auto& hi = bins_.hi();
  const int ex = hi[0] - lo[0] + 1, ey = hi[1] - lo[1] + 1, ez = hi[2] - lo[2] + 1;
  cell_grad_.resize(std::size_t(ex) * ey * ez);
  cell_open_.resize(cell_grad_.size());
  const double inv = 1.0 / grid_.h;
  const std::int64_t sx = grid_.cells[0] + 1, sxy = sx * (grid_.cells[1] + 1);
  // One row of cells along x per call; each cell writes only its own coefficients.
  auto row = [&](int jk) {
    const int j = jk % ey, k = jk / ey;
    for (int i = 0; i < ex; ++i) {
      const std::int64_t n0 = grid_.node_index(lo[0] + i, lo[1] + j, lo[2] + k);
      // v(a, b, c) = velocity of node n0 + a + b sx + c sxy.
      auto v = [&](int a, int b, int c) -> const Vec3& { return vel_[n0 + a + b * sx + c * sxy]; };
      const std::size_t cell = std::size_t(i) + std::size_t(ex) * (j + std::size_t(ey) * k);
      auto& G = cell_grad_[cell];
      bool open = false;
      for (int c = 0; c < 8; ++c) open = open || !(mass_[n0 + (c & 1) + ((c >> 1) & 1) * sx + (c >> 2) * sxy] > mass_eps_);
      cell_open_[cell] = open;
      for (int r = 0; r < 3; ++r) {
        // Column 0 (d/dx) in (fy, fz), column 1 (d/dy) in (fx, fz), column 2 (d/dz) in (fx, fy).
        const double dx[4] = {v(1, 0, 0)[r] - v(0, 0, 0)[r], v(1, 1, 0)[r] - v(0, 1, 0)[r],
                              v(1, 0, 1)[r] - v(0, 0, 1)[r], v(1, 1, 1)[r] - v(0, 1, 1)[r]};
        const double dy[4] = {v(0, 1, 0)[r] - v(0, 0, 0)[r], v(1, 1, 0)[r] - v(1, 0, 0)[r],
                              v(0, 1, 1)[r] - v(0, 0, 1)[r], v(1, 1, 1)[r] - v(1, 0, 1)[r]};
        const double dz[4] = {v(0, 0, 1)[r] - v(0, 0, 0)[r], v(1, 0, 1)[r] - v(1, 0, 0)[r],
                              v(0, 1, 1)[r] - v(0, 1, 0)[r], v(1, 1, 1)[r] - v(1, 1, 0)[r]};
        const double* d[3] = {dx, dy, dz};
        for (int col = 0; col < 3; ++col) {
          // d[col] = {D(0,0), D(1,0), D(0,1), D(1,1)} in the column's two fractions.
          const double* D = d[col];
          G[12 * col + r] = inv * D[0];
          G[12 * col + 3 + r] = inv * (D[1] - D[0]);
          G[12 * col + 6 + r] = inv * (D[2] - D[0]);
          G[12 * col + 9 + r] = inv * ((D[3] - D[2]) - (D[1] - D[0]));
        }
      }
    }
  };
  if (cell_grad_.size() < 8192) {  // small box: task overhead dominates
    for (int jk = 0; jk < ey * ez; ++jk) row(jk);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, ey * ez, 16), [&](const tbb::blocked_range<int>& r) {
    for (int jk = r.begin(); jk != r.end(); ++jk) row(jk);
  });
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

inline Mat3 MpmSolver::velocity_gradient(const double f[3], std::size_t cell) const {
  const auto& G = cell_grad_[cell];
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

MpmSolver::MpmSolver(Grid grid, std::vector<Material> materials, Particles particles, MpmOptions options)
    : grid_(std::move(grid)), materials_(std::move(materials)), particles_(std::move(particles)),
      options_(options) {
  if (materials_.empty()) throw std::invalid_argument("MpmSolver: no materials given");
  for (const auto& m : materials_) m.validate();
  const auto n = particles_.size();
  if (particles_.x.size() != n || particles_.v.size() != n || particles_.stress.size() != n ||
      particles_.rho.size() != n || particles_.energy.size() != n || particles_.material.size() != n)
    throw std::invalid_argument("MpmSolver: particle arrays have different sizes");
  double total_mass = 0;
  for (std::size_t p = 0; p < n; ++p) {
    std::ostringstream where;
    where << "MpmSolver: particle " << p << " at (" << particles_.x[p].transpose() << ")";
    if (particles_.material[p] >= materials_.size())
      throw std::invalid_argument(where.str() + " has material index out of range");
    if (!(particles_.mass[p] > 0) || !(particles_.rho[p] > 0))
      throw std::invalid_argument(where.str() + " has non-positive mass or density");
    if (!grid_.contains(particles_.x[p])) throw std::invalid_argument(where.str() + " is outside the grid");
    total_mass += particles_.mass[p];
  }
  for (const auto& m : materials_)
    lame_.push_back({m.lame_lambda(), 2.0 * m.shear_modulus(), m.lame_lambda() + 2 * m.shear_modulus()});
  for (const auto& m : materials_) inv_rho0_.push_back(1.0 / m.rho0);
  mask_ = grid_.build_constraint_mask();
  const auto nn = static_cast<std::size_t>(grid_.num_nodes());
  mass_.assign(nn, 0.0);
  for (auto* f : {&mom_old_, &mom_new_, &force_, &impulse_, &vel_, &dvel_, &dvel_imp_})
    f->assign(nn, Vec3::Zero());
  mass_eps_ = n ? 1e-12 * total_mass / double(n) : 0.0;
  critical_dt_ = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < n; ++p)
    critical_dt_ = std::min(critical_dt_, particle_step_bound(materials_[particles_.material[p]],
                                                              lame_[particles_.material[p]][2], particles_.rho[p],
                                                              particles_.stress[p], particles_.v[p], grid_.h));
  critical_dt_ *= options_.cfl;
}

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

template <class F>
void MpmSolver::add_cell_corners(int j, int k, std::int64_t first, F&& f) const {
  // Node (i, j, k) is corner d = (dx, dy, dz) of cell (i - dx, j - dy, k - dz). Per node the cells
  // come in the order (dz, dy, dx) = (1, 1, 1), (1, 1, 0), (1, 0, 1), ..., (0, 0, 0).
  const auto& lo = bins_.lo();
  const auto& hi = bins_.hi();
  const int ex = hi[0] - lo[0] + 1;
  for (int dz = 1; dz >= 0; --dz) {
    if (k - dz < lo[2] || k - dz > hi[2]) continue;
    for (int dy = 1; dy >= 0; --dy) {
      if (j - dy < lo[1] || j - dy > hi[1]) continue;
      const std::size_t c0 = box_cell({lo[0], j - dy, k - dz});
      const int corner = 2 * dy + 4 * dz;
      for (int ci = 0; ci < ex; ++ci) {
        f(first + ci + 1, c0 + ci, corner + 1);  // the cell's corner dx = 1
        f(first + ci, c0 + ci, corner);          // dx = 0
      }
    }
  }
}

void MpmSolver::trial_step(double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("MpmSolver: time step must be positive");
  auto& P = particles_;
  dt_step_ = dt;
  // Variable steps (section 3.2, Fig. 2): the velocities v^{n-1/2} act over the last step
  // dt^{n-1/2}, and momentum advances by dt^n = (dt^{n-1/2} + dt^{n+1/2}) / 2 (eqs. 16, 64).
  // The strain increment of eq. (62) is printed with dt^n; it is taken over dt^{n-1/2}, the interval
  // over which those velocities moved the particles, so that with a varying step an elastic body's
  // stress keeps following its displacement (with dt^n it does not: a step pattern that lands on
  // output times, 57 steps then two shorter ones, pumped energy into the sphere-on-membrane example
  // at cell 2 mm). Equal steps give dt^n = dt^{n-1/2} = dt, bit for bit.
  const double dt_strain = dt_prev_ > 0 ? dt_prev_ : dt;
  dt_n_ = 0.5 * (dt_strain + dt);
  // Step 1: reset the nodes of the previous step's box (the grid is "rebuilt" each step): the
  // accumulated fields, and p^{n+1/2} (zero outside the box for callers). The per-phase velocities
  // vel_, dvel_, dvel_imp_ are overwritten on the whole new box before they are read; impulses are
  // non-zero only at impulse_nodes_.
  for_each_box_node([&](std::int64_t id) {
    mass_[id] = 0;
    for (auto* f : {&mom_old_, &mom_new_, &force_}) (*f)[id].setZero();
  });
  for (auto id : impulse_nodes_) impulse_[id].setZero();
  impulse_nodes_.clear();
  work_.resize(P.size());
  bins_.build(grid_, P.x);
  if (bins_.empty()) {
    box_lo_ = {0, 0, 0};
    box_hi_ = {-1, -1, -1};
    return;
  }
  for (int a = 0; a < 3; ++a) {
    box_lo_[a] = bins_.lo()[a];
    box_hi_[a] = bins_.hi()[a] + 1;
  }

  // Step 2a (eqs. 60, 61) in per-cell form (cell_moments.hpp): corner masses and momenta per cell,
  // then per node (eq. 51 only where contact asks for it: particle_trial_momenta).
  const auto ncell = std::size_t(bins_.hi()[0] - bins_.lo()[0] + 1) * (bins_.hi()[1] - bins_.lo()[1] + 1) *
                     (bins_.hi()[2] - bins_.lo()[2] + 1);
  cell_acc_.resize(ncell);
  bins_.for_each_cell([&](const std::array<int, 3>& c, const std::uint32_t* b, const std::uint32_t* e) {
    CellAcc acc{};  // local: no aliasing with the particle arrays
    for (auto it = b; it != e; ++it) {
      double f[3];
      grid_.fractions(P.x[*it], c, f);
      add_mass_moments(f, P.mass[*it], P.v[*it], acc);
    }
    cell_acc_[box_cell(c)] = acc;
  });
  // Step 2b: essential conditions on p^{n-1/2}; grid velocities v_I = p_I / m_I (0 if empty).
  const int nx = box_hi_[0] - box_lo_[0] + 1;
  for_each_box_row([&](std::int64_t first, int j, int k) {
    for (std::int64_t id = first; id < first + nx; ++id) {
      mass_[id] = 0;
      mom_old_[id].setZero();
    }
    add_cell_corners(j, k, first, [&](std::int64_t id, std::size_t cell, int corner) {
      const CellAcc& acc = cell_acc_[cell];
      mass_[id] += acc[corner];
      for (int r = 0; r < 3; ++r) mom_old_[id][r] += acc[8 * (1 + r) + corner];
    });
    for (std::int64_t id = first; id < first + nx; ++id) {
      for (int a = 0; a < 3; ++a)
        if (mask_[id][a]) mom_old_[id][a] = 0.0;
      vel_[id] = mass_[id] > mass_eps_ ? Vec3(mom_old_[id] / mass_[id]) : Vec3::Zero();
    }
  });
  cell_gradients();
  const double inv_h = 1.0 / grid_.h;
  // Steps 2c, 2d (eqs. 62, 63, 22, 25, 26; 17): stress update, then the particle's stress moments
  // (cell_moments.hpp), in the same pass over the cells. A cell with a corner without mass holds
  // in practice only particles on its faces (rare): their stencils are closed (close_stencil) and
  // their velocity gradients and corner forces taken from the full 8-node stencils.
  bins_.for_each_cell([&](const std::array<int, 3>& c, const std::uint32_t* b, const std::uint32_t* e) {
    const std::size_t cell = box_cell(c);
    CellAcc acc{};  // local: no aliasing with the particle arrays
    const bool open = cell_open_[cell];
    StressBatch bt;
    for (auto it = b; it != e; ++it) {
      const std::size_t p = *it;
      if (!open) {
        double* f = bt.f[bt.n];
        grid_.fractions(P.x[p], c, f);
        const double V = update_particle_stress(p, dt_strain, velocity_gradient(f, cell));
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
        const double V = update_particle_stress(p, dt_strain, L);
        double A[3][3];  // -V sigma of eq. (17)
        for (int r = 0; r < 3; ++r)
          for (int col = 0; col < 3; ++col) A[r][col] = -V * P.stress[p](r, col);
        add_corner_forces(st, A, acc);
      }
    }
    if (!open)
      for (auto& a : acc) a *= inv_h;  // the 1 / h of dN/dx (cell_moments.hpp)
    cell_acc_[cell] = acc;
  });
  // Step 2e: nodal forces (eq. 17 from the cells, eq. 18 as m_I g), grid conditions on f, trial
  // momentum p^{n+1/2} (eq. 64).
  const Vec3 g = options_.gravity;
  for_each_box_row([&](std::int64_t first, int j, int k) {
    for (std::int64_t id = first; id < first + nx; ++id) force_[id].setZero();
    add_cell_corners(j, k, first, [&](std::int64_t id, std::size_t cell, int corner) {
      const CellAcc& acc = cell_acc_[cell];
      if (cell_open_[cell])
        force_[id] += Vec3(acc[3 * corner], acc[3 * corner + 1], acc[3 * corner + 2]);
      else
        force_[id] += corner_force_moment(acc, corner);
    });
    for (std::int64_t id = first; id < first + nx; ++id) {
      force_[id] += mass_[id] * g;
      for (int a = 0; a < 3; ++a)
        if (mask_[id][a]) force_[id][a] = 0.0;
      mom_new_[id] = mom_old_[id] + dt_n_ * force_[id];
    }
  });
}

double MpmSolver::update_particle_stress(std::size_t p, double dt, const Mat3& L) {
  auto& P = particles_;
  // D = sym L (eq. 23), W = skew L (eq. 24).
  const Mat3 D = 0.5 * (L + L.transpose());
  const double trD = D.trace();
  const auto& mat = materials_[P.material[p]];
  const double rho_old = P.rho[p];
  // Mass conservation: rho^{n+1} = rho^n exp(-dt tr D).
  const double shrink = exp_small(-dt * trD);
  const double rho_new = rho_old * shrink;
  P.rho[p] = rho_new;
  if (mat.kind == Material::Kind::LinearElastic) {
    // Hypo-elastic Jaumann update (eqs. 22, 25): sigma += dt (C:D + W sigma - sigma W).
    // Eq. (22) is printed as sigma Omega + (sigma Omega)^T; with Omega_ij = (v_i,j - v_j,i)/2 as in
    // eq. (24) the objective rotation of sigma is W sigma - sigma W, which is what is used.
    const Mat3 W = 0.5 * (L - L.transpose());
    const Mat3& s = P.stress[p];
    const auto& lm = lame_[P.material[p]];  // lambda, 2 G
    const Mat3 rate = lm[0] * trD * Mat3::Identity() + lm[1] * D;
    P.stress[p] = s + dt * (rate + W * s - s * W);
    return P.mass[p] / rho_new;
  }
  // Fluid (eq. 26): sigma = 2 mu D' - p I, p from the EOS with the energy equation
  //   dE = (s_visc : D dt) V/V0 - (p^n + p^{n+1})/2 dV/V0,
  // solved exactly for E^{n+1} because both EOS are linear in E (p = a + b E).
  // Volume ratios V/V0 = rho0/rho with V^{n+1}/V^n = exp(dt tr D): one division, off the path
  // from tr D to the stress, instead of the chain of m/rho0, m/rho^n, m/rho^{n+1}, dV/V0 and the
  // EOS's rho/rho0 (that chain of dependent divisions was the critical path of the update).
  constexpr double kThird = 1.0 / 3.0;
  const double inv_rho0 = inv_rho0_[P.material[p]];
  const double r_old = mat.rho0 / rho_old, r_new = r_old * exp_small(dt * trD);
  const double dv = r_new - r_old;
  const double mean = trD * kThird;
  Mat3 Ddev = D;
  for (int a = 0; a < 3; ++a) Ddev(a, a) -= mean;
  const double two_mu = 2.0 * mat.viscosity;
  const double w_visc = two_mu * Ddev.squaredNorm() * dt * 0.5 * (r_old + r_new);
  const Mat3& s_old = P.stress[p];
  const double p_old = -(s_old(0, 0) + s_old(1, 1) + s_old(2, 2)) * kThird;
  // Ideal gas (eq. 67): p = (gamma - 1) (rho / rho0) E, with rho / rho0 = 1 / r_new.
  const auto [a, b] = mat.eos == Eos::IdealGas ? std::pair<double, double>{0.0, (mat.gamma - 1.0) * (rho_new * inv_rho0)}
                                               : mat.eos_coefficients(rho_new);
  const double E = (P.energy[p] + w_visc - 0.5 * (p_old + a) * dv) / (1.0 + 0.5 * b * dv);
  P.energy[p] = E;
  const double pressure = a + b * E;
  Mat3& s = P.stress[p];
  s = two_mu * Ddev;
  for (int a = 0; a < 3; ++a) s(a, a) -= pressure;
  return (P.mass[p] * inv_rho0) * r_new;  // V = V0 r_new
}

void MpmSolver::add_node_impulse(std::int64_t node, const Vec3& dp) {
  Vec3 d = dp;
  for (int a = 0; a < 3; ++a)
    if (mask_[node][a]) d[a] = 0.0;
  if (impulse_[node].isZero(0.0)) impulse_nodes_.push_back(node);
  impulse_[node] += d;
}

const std::vector<std::array<int, 3>>& MpmSolver::cells_around(const std::vector<std::int64_t>& nodes) {
  around_.clear();
  if (bins_.empty()) return around_;
  const auto& lo = bins_.lo();
  const auto& hi = bins_.hi();
  const int ex = hi[0] - lo[0] + 1, ey = hi[1] - lo[1] + 1, ez = hi[2] - lo[2] + 1;
  cell_mark_.resize(std::size_t(ex) * ey * ez, 0);  // all zero between calls
  const std::int64_t nx = grid_.cells[0] + 1, ny = grid_.cells[1] + 1;
  int kmin = ez, kmax = -1;
  for (auto node : nodes) {
    const int i = static_cast<int>(node % nx), j = static_cast<int>((node / nx) % ny), k = static_cast<int>(node / (nx * ny));
    for (int ck = std::max(k - 1, lo[2]); ck <= std::min(k, hi[2]); ++ck)
      for (int cj = std::max(j - 1, lo[1]); cj <= std::min(j, hi[1]); ++cj)
        for (int ci = std::max(i - 1, lo[0]); ci <= std::min(i, hi[0]); ++ci) {
          cell_mark_[std::size_t(ci - lo[0]) + std::size_t(ex) * ((cj - lo[1]) + std::size_t(ey) * (ck - lo[2]))] = 1;
          kmin = std::min(kmin, ck - lo[2]);
          kmax = std::max(kmax, ck - lo[2]);
        }
  }
  // Scan in k, j, i order: ascending global cell index; clear the marks on the way.
  for (int k = kmin; k <= kmax; ++k)
    for (int j = 0; j < ey; ++j)
      for (int i = 0; i < ex; ++i) {
        auto& m = cell_mark_[std::size_t(i) + std::size_t(ex) * (j + std::size_t(ey) * k)];
        if (!m) continue;
        m = 0;
        around_.push_back({lo[0] + i, lo[1] + j, lo[2] + k});
      }
  return around_;
}

void MpmSolver::particle_trial_momenta(const std::vector<std::int64_t>& nodes, std::vector<Vec3>& out,
                                       std::vector<Vec3>* mass_gradient) {
  if (marked_.size() != mass_.size()) marked_.assign(mass_.size(), 0);
  for (auto node : nodes) {
    marked_[node] = 1;
    out[node].setZero();
    if (mass_gradient) (*mass_gradient)[node].setZero();
  }
  // The particles of the cells around the nodes, per cell: the corner velocity changes
  // (p^{n+1/2} - p^{n-1/2}) / m (0 at empty corners) are formed once, and the cell's particles
  // give per corner sum_p m_p N_Ip v~_p and sum_p m_p N_Ip,i. Cells run in parallel (each writes
  // only its own sums); the sums are then added to the marked nodes cell by cell in ascending
  // index, so the result does not depend on the number of threads.
  const double inv_h = 1.0 / grid_.h;
  const auto& cells = cells_around(nodes);
  around_acc_.resize(cells.size());
  auto cell_sums = [&](std::size_t k) {
    const auto& c = cells[k];
    auto& acc = around_acc_[k];
    acc.fill(0.0);
    const auto [b, e] = bins_.cell(c[0], c[1], c[2]);
    if (b == e) return;
    std::int64_t id[8];
    corner_nodes(grid_, c, id);
    Vec3 dvc[8];
    for (int q = 0; q < 8; ++q)
      dvc[q] = mass_[id[q]] > mass_eps_ ? Vec3((mom_new_[id[q]] - mom_old_[id[q]]) / mass_[id[q]]) : Vec3::Zero();
    for (auto it = b; it != e; ++it) {
      const std::size_t p = *it;
      double f[3], N[8];
      grid_.fractions(particles_.x[p], c, f);
      corner_weights(f, N);
      Vec3 v = particles_.v[p];
      for (int q = 0; q < 8; ++q) v += N[q] * dvc[q];
      for (int q = 0; q < 8; ++q) {
        if (!marked_[id[q]]) continue;
        const Vec3 mv = (particles_.mass[p] * N[q]) * v;
        for (int r = 0; r < 3; ++r) acc[6 * q + r] += mv[r];
        if (mass_gradient) {
          const Vec3 g = particles_.mass[p] * corner_gradient(f, q, inv_h);
          for (int r = 0; r < 3; ++r) acc[6 * q + 3 + r] += g[r];
        }
      }
    }
  };
  for_each_index(cells.size(), particles_.size() >= CellBins::kParallelMin, cell_sums);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    std::int64_t id[8];
    corner_nodes(grid_, cells[k], id);
    const auto& acc = around_acc_[k];
    for (int q = 0; q < 8; ++q) {
      if (!marked_[id[q]]) continue;
      out[id[q]] += Vec3(acc[6 * q], acc[6 * q + 1], acc[6 * q + 2]);
      if (mass_gradient) (*mass_gradient)[id[q]] += Vec3(acc[6 * q + 3], acc[6 * q + 4], acc[6 * q + 5]);
    }
  }
  for (auto node : nodes) marked_[node] = 0;
}

void MpmSolver::finish_step(double dt) {
  if (dt != dt_step_) throw std::invalid_argument("MpmSolver: finish_step got another step than trial_step");
  auto& P = particles_;
  const std::size_t n = P.size();
  const bool impulses = !impulse_nodes_.empty();
  // Per node: velocity change (p^{n+1/2} - p^{n-1/2}) / m (eq. 65), its impulse part, and the new
  // velocity (eq. 19).
  for_each_box_node([&](std::int64_t id) {
    const bool full = mass_[id] > mass_eps_;
    const Vec3 p_new = mom_new_[id] + impulse_[id];
    dvel_[id] = full ? Vec3((p_new - mom_old_[id]) / mass_[id]) : Vec3::Zero();
    dvel_imp_[id] = full ? Vec3(impulse_[id] / mass_[id]) : Vec3::Zero();
    vel_[id] = full ? Vec3(p_new / mass_[id]) : Vec3::Zero();
  });
  // Grid-to-particle update (eqs. 65, 19) cell by cell: the 8 corner values of a cell are read
  // once for all its particles. Per cell, the reductions of this step (next critical step, eq. 21,
  // and the first invalid particle; max / min are exact, so their order does not matter); the
  // impulse work is stored per particle and summed in particle order below.
  const double h = grid_.h, inv_h = 1.0 / h;
  // Explicit viscous bound rho h^2 / (8 mu) as rho times a per-material factor (infinite unless a
  // viscous fluid): no division per particle.
  bool viscous = false;
  visc_factor_.clear();
  for (const auto& m : materials_) {
    visc_factor_.push_back(viscous_bound(m, 1.0, h));
    viscous = viscous || visc_factor_.back() < std::numeric_limits<double>::infinity();
  }
  cell_bounds_.resize(cell_acc_.size());
  bins_.for_each_cell([&](const std::array<int, 3>& c, const std::uint32_t* b, const std::uint32_t* e) {
    StepBounds a;
    if (b != e) {
      std::int64_t id[8];
      corner_nodes(grid_, c, id);
      // Corner values in rows (dv_I, v_I) and dv^imp_I (packed: the sums below vectorise).
      double dvv[8][6], dvi_c[8][3];
      bool cell_impulses = false;  // some corner got a contact impulse (else dv^imp = 0 exactly)
      for (int q = 0; q < 8; ++q)
        for (int r = 0; r < 3; ++r) {
          dvv[q][r] = dvel_[id[q]][r];
          dvv[q][3 + r] = vel_[id[q]][r];
          dvi_c[q][r] = dvel_imp_[id[q]][r];
          cell_impulses = cell_impulses || dvi_c[q][r] != 0.0;
        }
      for (auto it = b; it != e; ++it) {
        const std::size_t p = *it;
        double f[3];
        grid_.fractions(P.x[p], c, f);
        double N[8];
        corner_weights(f, N);
        double s6[6] = {0, 0, 0, 0, 0, 0};  // sum_I N_Ip dv_I, sum_I N_Ip v_I
        for (int q = 0; q < 8; ++q)
          for (int r = 0; r < 6; ++r) s6[r] += N[q] * dvv[q][r];
        const Vec3 dv(s6[0], s6[1], s6[2]), vel(s6[3], s6[4], s6[5]);
        if (impulses && !cell_impulses) {
          work_[p] = 0.0;
        } else if (impulses) {
          double s3[3] = {0, 0, 0};
          for (int q = 0; q < 8; ++q)
            for (int r = 0; r < 3; ++r) s3[r] += N[q] * dvi_c[q][r];
          const Vec3 dvi(s3[0], s3[1], s3[2]);
          work_[p] = P.mass[p] * dvi.dot(P.v[p] + 0.5 * dv);  // dvi . (v^{n-1/2} + v^{n+1/2}) / 2
        }
        P.v[p] += dv;
        P.x[p] += dt * vel;
        const auto mat = P.material[p];
        const double speed = particle_speed(materials_[mat], lame_[mat][2], P.rho[p], P.stress[p], P.v[p]);
        a.c_max = std::max(a.c_max, speed);
        if (viscous) a.dt = std::min(a.dt, P.rho[p] * visc_factor_[mat]);
        const bool inside = grid_.contains(P.x[p], inv_h);  // false for a non-finite position too
        // One finiteness test on a sum (a NaN or an infinity in any term makes it non-finite; an
        // overflow of finite terms only sends the step to check_particles, which looks again).
        const Mat3& sg = P.stress[p];
        const double sum = ((P.v[p][0] + P.v[p][1]) + (P.v[p][2] + P.rho[p])) +
                           ((sg(0, 0) + sg(1, 1)) + (sg(2, 2) + sg(0, 1))) +
                           ((sg(1, 0) + sg(0, 2)) + (sg(2, 0) + (sg(1, 2) + sg(2, 1))));
        // A NaN wave speed (e.g. from a non-positive density) would drop out of the max above.
        const bool ok = inside && std::isfinite(sum) && std::isfinite(speed);
        if (!ok) a.bad = std::min(a.bad, p);
      }
    }
    cell_bounds_[box_cell(c)] = a;
  });
  StepBounds acc;
  for (const auto& a : cell_bounds_) {
    acc.c_max = std::max(acc.c_max, a.c_max);
    acc.dt = std::min(acc.dt, a.dt);
    acc.bad = std::min(acc.bad, a.bad);
  }
  impulse_work_ = !impulses ? 0.0
                             : deterministic_reduce(
                                   n, kGrain, kSerialBelow, 0.0,
                                   [&](const tbb::blocked_range<std::size_t>& r, double w) {
                                     for (std::size_t p = r.begin(); p != r.end(); ++p) w += work_[p];
                                     return w;
                                   },
                                   [](double a, double b) { return a + b; });
  critical_dt_ = options_.cfl * std::min(sound_bound(acc.c_max, h), acc.dt);
  if (acc.bad < n) check_particles(dt);
  dt_prev_ = dt;
  time_ += dt;
  ++steps_;
}

void MpmSolver::check_particles(double dt) const {
  const auto& P = particles_;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!P.x[p].allFinite() || !P.v[p].allFinite() || !P.stress[p].allFinite() || !std::isfinite(P.rho[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " became non-finite at step " << steps_ + 1 << " (t = " << time_ + dt
          << "); the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
    if (!grid_.contains(P.x[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " left the background grid at (" << P.x[p].transpose()
          << ") at t = " << time_ + dt;
      throw std::runtime_error(msg.str());
    }
    if (!(P.rho[p] > 0)) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " has a non-positive density " << P.rho[p] << " at t = " << time_ + dt
          << "; the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
  }
}

void MpmSolver::step(double dt) {
  trial_step(dt);
  finish_step(dt);
}

MpmEnergies MpmSolver::energies() const {
  const auto& P = particles_;
  auto sum = [](MpmEnergies a, const MpmEnergies& b) {
    a.kinetic += b.kinetic;
    a.internal += b.internal;
    a.gravity += b.gravity;
    return a;
  };
  return deterministic_reduce(
      P.size(), kGrain, kSerialBelow, MpmEnergies{},
      [&](const tbb::blocked_range<std::size_t>& r, MpmEnergies e) {
        for (std::size_t p = r.begin(); p != r.end(); ++p) {
          const auto& mat = materials_[P.material[p]];
          e.kinetic += 0.5 * P.mass[p] * P.v[p].squaredNorm();
          e.gravity -= P.mass[p] * options_.gravity.dot(P.x[p]);
          if (mat.kind == Material::Kind::Fluid) {
            e.internal += P.energy[p] * P.mass[p] / mat.rho0;
          } else {
            // W = 1/2 sigma : eps V with eps = ((1+nu) sigma - nu tr(sigma) I) / E.
            const Mat3& s = P.stress[p];
            const Mat3 eps = ((1 + mat.poisson) * s - mat.poisson * s.trace() * Mat3::Identity()) / mat.youngs;
            e.internal += 0.5 * s.cwiseProduct(eps).sum() * P.volume(p);
          }
        }
        return e;
      },
      sum);
}

Vec3 MpmSolver::total_momentum() const {
  Vec3 m = Vec3::Zero();
  for (std::size_t p = 0; p < particles_.size(); ++p) m += particles_.mass[p] * particles_.v[p];
  return m;
}

}  // namespace tetfsi::mpm
