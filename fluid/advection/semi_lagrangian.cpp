#include "fluid/advection/semi_lagrangian.hpp"

#include <tbb/parallel_for.h>

#include <atomic>
#include <stdexcept>

namespace tetfsi::fluid {
namespace {

struct NodalFields {
  TetVectors u;
  Eigen::VectorXd s, temp;
};

Eigen::Vector3d interp(const FluidMesh& m, const TetVectors& f, const Location& l) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) v += l.bary[k] * f[m.tets[l.tet][k]];
  return v;
}

double interp(const FluidMesh& m, const Eigen::VectorXd& f, const Location& l) {
  double v = 0.0;
  for (int k = 0; k < 4; ++k) v += l.bary[k] * f[m.tets[l.tet][k]];
  return v;
}

/// Moves from `from` (inside, at `from_loc`) towards `to`; returns the location of `to` if inside,
/// else of the last inside point found by bisection on the segment.
Location trace_to(const PointLocator& loc, const Eigen::Vector3d& from, const Location& from_loc,
                  const Eigen::Vector3d& to, int& clamped) {
  Location l = loc.locate(to, from_loc.tet);
  if (l.inside) return l;
  ++clamped;
  Eigen::Vector3d a = from, b = to;
  Location la = from_loc;
  for (int it = 0; it < 12; ++it) {
    const Eigen::Vector3d mid = 0.5 * (a + b);
    Location lm = loc.locate(mid, la.tet);
    if (lm.inside) {
      a = mid;
      la = lm;
    } else {
      b = mid;
    }
  }
  return la;
}

}  // namespace

FluidFields advect(const FluidMesh& old_mesh, const FluidFields& old_fields, const FluidMesh& new_mesh, double dt,
                   AdvectionReport* report) {
  if (static_cast<int>(old_fields.velocity.size()) != old_mesh.num_tets() ||
      old_fields.smoke.size() != old_mesh.num_tets() || old_fields.temperature.size() != old_mesh.num_tets())
    throw std::invalid_argument("advect: old fields do not match the old mesh's tet count");
  NodalFields nodal{average_to_nodes(old_mesh, old_fields.velocity), average_to_nodes(old_mesh, old_fields.smoke),
                    average_to_nodes(old_mesh, old_fields.temperature)};
  const PointLocator locator(old_mesh);
  const int n = new_mesh.num_tets();
  FluidFields out;
  out.velocity.resize(n);
  out.smoke.resize(n);
  out.temperature.resize(n);
  std::atomic<int> clamped_total{0}, outside_total{0};
  constexpr int kBlock = 256;
  const int blocks = (n + kBlock - 1) / kBlock;
  tbb::parallel_for(0, blocks, [&](int b) {
    int hint = -1, clamped = 0, outside = 0;
    for (int t = b * kBlock; t < std::min(n, (b + 1) * kBlock); ++t) {
      const Eigen::Vector3d x0 = new_mesh.centroid(t);
      const Location l0 = locator.locate(x0, hint);
      hint = l0.tet;
      Location l1 = l0;
      if (!l0.inside) {
        ++outside;
      } else {
        const Eigen::Vector3d u0 = interp(old_mesh, nodal.u, l0);
        const Eigen::Vector3d xm = x0 - 0.5 * dt * u0;
        const Location lm = trace_to(locator, x0, l0, xm, clamped);
        const Eigen::Vector3d um = interp(old_mesh, nodal.u, lm);
        l1 = trace_to(locator, x0, l0, x0 - dt * um, clamped);
      }
      out.velocity[t] = interp(old_mesh, nodal.u, l1);
      out.smoke[t] = interp(old_mesh, nodal.s, l1);
      out.temperature[t] = interp(old_mesh, nodal.temp, l1);
    }
    clamped_total += clamped;
    outside_total += outside;
  });
  if (report) {
    report->clamped = clamped_total;
    report->outside_start = outside_total;
  }
  return out;
}

}  // namespace tetfsi::fluid
