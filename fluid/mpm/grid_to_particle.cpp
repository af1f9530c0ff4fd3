/// @file grid_to_particle.cpp
/// Steps (65) and (19) of the MPM step (finish_step): particle velocities and positions from the
/// grid, the next critical step of eq. (21) and the finiteness check.
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


}  // namespace tetfsi::mpm
