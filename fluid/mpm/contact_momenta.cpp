/// @file contact_momenta.cpp
/// What the grid contact (coupling/mpm/grid_contact.hpp) asks of the particles: the cells around
/// given nodes, the momentum the particles carry to them after the trial update (eq. 51 and the
/// particle-side momenta), and impulses added to the grid.
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


}  // namespace tetfsi::mpm
