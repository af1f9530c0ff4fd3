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
double particle_speed(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v) {
  const double sound = mat.kind == Material::Kind::LinearElastic ? std::sqrt(p_modulus / rho)
                                                                 : mat.sound_speed(rho, -stress.trace() / 3.0);
  return sound + v.norm();
}

/// Explicit viscous bound rho dx^2 / (8 mu) [s] (infinite unless a viscous fluid).
double viscous_bound(const Material& mat, double rho, double dx) {
  if (mat.kind == Material::Kind::Fluid && mat.viscosity > 0) return rho * dx * dx / (8.0 * mat.viscosity);
  return std::numeric_limits<double>::infinity();
}

/// dx / c for the largest c > 0 (infinite if none): equal to the smallest dx / c_p, since rounded
/// division is monotone, with one division per step instead of one per particle.
double sound_bound(double c_max, double dx) {
  return c_max > 0 ? dx / c_max : std::numeric_limits<double>::infinity();
}

double particle_step_bound(const Material& mat, double p_modulus, double rho, const Mat3& stress, const Vec3& v,
                           double dx) {
  return std::min(sound_bound(particle_speed(mat, p_modulus, rho, stress, v), dx), viscous_bound(mat, rho, dx));
}

/// exp(x) for the density update: the Taylor polynomial to x^5 when |x| < 2^-10 (truncation below
/// x^6 / 720 < 2e-21, far under the rounding of the result; in the gas expansion h ~ 6e-5 and
/// |tr D| is of order 1), std::exp otherwise. The call to exp was ~5% of the gas expansion's
/// particle work.
double exp_small(double x) {
  if (std::abs(x) >= 0x1p-10) return std::exp(x);
  return 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0)))));
}

}  // namespace

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
  // The message is formatted only for a bad particle (formatting every particle's position was a
  // quarter of the set-up of a 113k-particle body).
  auto where = [&](std::size_t p) {
    std::ostringstream s;
    s << "MpmSolver: particle " << p << " at (" << particles_.x[p].transpose() << ")";
    return s.str();
  };
  for (std::size_t p = 0; p < n; ++p) {
    if (particles_.material[p] >= materials_.size())
      throw std::invalid_argument(where(p) + " has material index out of range");
    if (!(particles_.mass[p] > 0) || !(particles_.rho[p] > 0))
      throw std::invalid_argument(where(p) + " has non-positive mass or density");
    if (!grid_.contains(particles_.x[p])) throw std::invalid_argument(where(p) + " is outside the grid");
    const Mat3& sg = particles_.stress[p];  // the stress update keeps sigma symmetric; it must start so
    if (sg(0, 1) != sg(1, 0) || sg(0, 2) != sg(2, 0) || sg(1, 2) != sg(2, 1))
      throw std::invalid_argument(where(p) + " has a non-symmetric stress");
    total_mass += particles_.mass[p];
  }
  for (const auto& m : materials_)
    lame_.push_back({m.lame_lambda(), 2.0 * m.shear_modulus(), m.lame_lambda() + 2 * m.shear_modulus()});
  for (const auto& m : materials_) inv_rho0_.push_back(1.0 / m.rho0);
  for (std::size_t m = 0; m < materials_.size(); ++m) {
    elastic_.push_back(materials_[m].kind == Material::Kind::LinearElastic);
    inv_p_modulus_.push_back(elastic_.back() ? 1.0 / lame_[m][2] : 0.0);
  }
  mask_ = grid_.build_constraint_mask();
  const auto nn = static_cast<std::size_t>(grid_.num_nodes());
  mass_.assign(nn, 0.0);
  for (auto* f : {&mom_old_, &mom_new_, &force_, &impulse_, &vel_, &dvel_, &dvel_imp_})
    f->assign(nn, Vec3::Zero());
  mass_eps_ = n ? 1e-12 * total_mass / double(n) : 0.0;
  critical_h_ = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < n; ++p)
    critical_h_ = std::min(critical_h_, particle_step_bound(materials_[particles_.material[p]],
                                                              lame_[particles_.material[p]][2], particles_.rho[p],
                                                              particles_.stress[p], particles_.v[p], grid_.dx));
  critical_h_ *= options_.cfl;
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
  const double inv_dx = 1.0 / grid_.dx;
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
          const Vec3 g = particles_.mass[p] * corner_gradient(f, q, inv_dx);
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

void MpmSolver::finish_step(double h) {
  if (h != h_step_) throw std::invalid_argument("MpmSolver: finish_step got another step than trial_step");
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
  const double dx = grid_.dx, inv_dx = 1.0 / dx;
  // Explicit viscous bound rho dx^2 / (8 mu) as rho times a per-material factor (infinite unless a
  // viscous fluid): no division per particle.
  bool viscous = false;
  visc_factor_.clear();
  for (const auto& m : materials_) {
    visc_factor_.push_back(viscous_bound(m, 1.0, dx));
    viscous = viscous || visc_factor_.back() < std::numeric_limits<double>::infinity();
  }
  cell_bounds_.resize(bins_.empty() ? 0 : cell_corners_.size());  // no particles: no bound (infinite step)
  const std::uint32_t* const ids_end = bins_.ids_end();
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
      // Elastic particles: c_p + |v_p| <= sqrt((lambda + 2 G) / rho_min) + |v|_max over the cell
      // (rho / (lambda + 2 G) and |v|^2 per particle, two square roots per cell instead of a
      // division and two roots per particle; the bound exceeds the cell's largest c + |v| by at most
      // the spread of |v| within the cell, parts per million of c in the sphere examples).
      double solid_rho_min = std::numeric_limits<double>::infinity(), solid_v2_max = 0;
      for (auto it = b; it != e; ++it) {
        const std::size_t p = *it;
        prefetch_ahead(it, ids_end, P.x, P.v, P.rho);
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
        P.x[p] += h * vel;
        const auto mat = P.material[p];
        double speed = 0;  // c + |v| of a fluid particle; elastic ones go into the cell's bound below
        if (elastic_[mat]) {
          solid_rho_min = std::min(solid_rho_min, P.rho[p] * inv_p_modulus_[mat]);
          solid_v2_max = std::max(solid_v2_max, P.v[p].squaredNorm());
        } else {
          speed = particle_speed(materials_[mat], lame_[mat][2], P.rho[p], P.stress[p], P.v[p]);
          a.c_max = std::max(a.c_max, speed);
        }
        if (viscous) a.h_viscous = std::min(a.h_viscous, P.rho[p] * visc_factor_[mat]);
        const bool inside = grid_.contains(P.x[p], inv_dx);  // false for a non-finite position too
        // Still in cell c? (the computation of Grid::cell_of, as CellBins uses it)
        if (inside)
          for (int k = 0; k < 3; ++k) a.moved = a.moved || static_cast<int>((P.x[p][k] - grid_.lo[k]) * inv_dx) != c[k];
        // One finiteness test on a sum (a NaN or an infinity in any term makes it non-finite; an
        // overflow of finite terms only sends the step to check_particles, which looks again).
        // The stresses were tested in the stress pass (cell_stress_bad_).
        const double sum = (P.v[p][0] + P.v[p][1]) + (P.v[p][2] + P.rho[p]);
        // A NaN wave speed (e.g. from a non-positive density) would drop out of the max above.
        const bool ok = inside && std::isfinite(sum) && std::isfinite(speed) && P.rho[p] > 0;  // rho > 0: no NaN
        if (!ok) a.bad = std::min(a.bad, p);
      }
      if (cell_stress_bad_[box_cell(c)]) a.bad = std::min(a.bad, std::size_t(*b));
      if (solid_rho_min < std::numeric_limits<double>::infinity())
        a.c_max = std::max(a.c_max, std::sqrt(1.0 / solid_rho_min) + std::sqrt(solid_v2_max));
    }
    cell_bounds_[box_cell(c)] = a;
  });
  StepBounds acc;
  for (const auto& a : cell_bounds_) {
    acc.c_max = std::max(acc.c_max, a.c_max);
    acc.h_viscous = std::min(acc.h_viscous, a.h_viscous);
    acc.bad = std::min(acc.bad, a.bad);
    acc.moved = acc.moved || a.moved;
  }
  // The next step may reuse this step's bins if no particle left its cell.
  bins_current_ = !acc.moved && acc.bad >= n;
  impulse_work_ = !impulses ? 0.0
                             : deterministic_reduce(
                                   n, kGrain, kSerialBelow, 0.0,
                                   [&](const tbb::blocked_range<std::size_t>& r, double w) {
                                     for (std::size_t p = r.begin(); p != r.end(); ++p) w += work_[p];
                                     return w;
                                   },
                                   [](double a, double b) { return a + b; });
  critical_h_ = options_.cfl * std::min(sound_bound(acc.c_max, dx), acc.h_viscous);
  if (acc.bad < n) check_particles(h);
  h_prev_ = h;
  time_ += h;
  ++steps_;
}

void MpmSolver::check_particles(double h) const {
  const auto& P = particles_;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (!P.x[p].allFinite() || !P.v[p].allFinite() || !P.stress[p].allFinite() || !std::isfinite(P.rho[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " became non-finite at step " << steps_ + 1 << " (t = " << time_ + h
          << "); the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
    if (!grid_.contains(P.x[p])) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " left the background grid at (" << P.x[p].transpose()
          << ") at t = " << time_ + h;
      throw std::runtime_error(msg.str());
    }
    if (!(P.rho[p] > 0)) {
      std::ostringstream msg;
      msg << "MpmSolver: particle " << p << " has a non-positive density " << P.rho[p] << " at t = " << time_ + h
          << "; the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
  }
}

void MpmSolver::step(double h) {
  trial_step(h);
  finish_step(h);
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
