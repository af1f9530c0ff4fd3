#include "solid/membrane/membrane.hpp"

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace tetfsi::membrane {

void MembraneMaterial::validate() const {
  auto fail = [](const std::string& w) { throw std::invalid_argument("membrane material: " + w); };
  if (!(rho > 0)) fail("density must be > 0");
  if (!(youngs > 0)) fail("Young's modulus must be > 0");
  if (!(poisson > -1 && poisson < 0.5)) fail("Poisson ratio must lie in (-1, 0.5)");
  if (!(thickness > 0)) fail("thickness must be > 0");
  if (!(hourglass >= 0) || !(hourglass_normal >= 0)) fail("hourglass coefficients must be >= 0");
}

namespace {
std::array<Vec3, 4> corners(const std::vector<Vec3>& x, const std::array<int, 4>& q) {
  return {x[q[0]], x[q[1]], x[q[2]], x[q[3]]};
}
}  // namespace

Membrane::Membrane(std::vector<Vec3> nodes, std::vector<std::array<int, 4>> quads, MembraneMaterial material)
    : x_(std::move(nodes)), quads_(std::move(quads)), mat_(material) {
  mat_.validate();
  const int n = num_nodes();
  v_.assign(n, Vec3::Zero());
  f_.assign(n, Vec3::Zero());
  f_ext_.assign(n, Vec3::Zero());
  mass_.assign(n, 0.0);
  fixed_.assign(n, {false, false, false});
  stress_.assign(quads_.size(), Eigen::Vector3d::Zero());
  hg_force_.assign(quads_.size(), Vec3::Zero());
  hg_k_.assign(quads_.size(), 0.0);
  for (std::size_t e = 0; e < quads_.size(); ++e) {
    for (int id : quads_[e])
      if (id < 0 || id >= n)
        throw std::invalid_argument("membrane: element " + std::to_string(e) + " has node id out of range");
    QuadFrame fr;
    try {
      fr = quad_frame(corners(x_, quads_[e]));
    } catch (const std::runtime_error& err) {
      throw std::runtime_error("membrane: element " + std::to_string(e) + ": " + err.what());
    }
    // Lumped mass: a quarter of rho t A per node.
    for (int id : quads_[e]) mass_[id] += 0.25 * mat_.rho * mat_.thickness * fr.area;
    double bb = 0;
    for (int k = 0; k < 4; ++k) bb += fr.b1[k] * fr.b1[k] + fr.b2[k] * fr.b2[k];
    hg_k_[e] = mat_.plate_modulus() * mat_.thickness * fr.area * bb;
  }
  for (int i = 0; i < n; ++i)
    if (!(mass_[i] > 0)) throw std::invalid_argument("membrane: node " + std::to_string(i) + " belongs to no element");
  // Node -> element corners (4 e + k), ascending in e, for the force gather.
  node_start_.assign(n + 1, 0);
  for (const auto& q : quads_)
    for (int id : q) ++node_start_[id + 1];
  for (int i = 0; i < n; ++i) node_start_[i + 1] += node_start_[i];
  node_corner_.assign(4 * quads_.size(), 0);
  std::vector<int> next(node_start_.begin(), node_start_.end() - 1);
  for (std::size_t e = 0; e < quads_.size(); ++e)
    for (int k = 0; k < 4; ++k) node_corner_[next[quads_[e][k]]++] = static_cast<int>(4 * e + k);
  corner_force_.assign(4 * quads_.size(), Vec3::Zero());
  pressure_force_.assign(quads_.size(), Vec3::Zero());
}

void Membrane::fix(int node, int axis) {
  if (node < 0 || node >= num_nodes() || axis < 0 || axis > 2)
    throw std::invalid_argument("membrane::fix: node or axis out of range");
  fixed_[node][axis] = true;
  v_[node][axis] = 0;
}

int Membrane::fix_where(const std::function<bool(const Vec3&)>& where, std::array<bool, 3> axes) {
  int count = 0;
  for (int i = 0; i < num_nodes(); ++i) {
    if (!where(x_[i])) continue;
    ++count;
    for (int a = 0; a < 3; ++a)
      if (axes[a]) fix(i, a);
  }
  return count;
}

double Membrane::critical_time_step(double cfl) const {
  const double c = std::sqrt(mat_.plate_modulus() / mat_.rho);
  double h = std::numeric_limits<double>::infinity();
  for (const auto& q : quads_) {
    const auto X = corners(x_, q);
    double lmax = 0;
    for (int k = 0; k < 4; ++k) lmax = std::max(lmax, (X[(k + 1) % 4] - X[k]).norm());
    const double area = 0.5 * (X[2] - X[0]).cross(X[3] - X[1]).norm();
    h = std::min(h, area / lmax / c);
  }
  return cfl * h;
}

void Membrane::compute_forces(double h) {
  const int n = num_nodes();
  // Variable steps (section 3.2): v^{n-1/2} moved the nodes over the last step h^{n-1/2}, so the
  // strain and hourglass increments and the mid-step geometry use it; eq. (46) then advances the
  // velocities by h^n = (h^{n-1/2} + h^{n+1/2}) / 2. Equal steps: all three are h, bit for bit.
  const double h_last = h_prev_ > 0 ? h_prev_ : h;
  h_n_ = 0.5 * (h_last + h);
  h_step_ = h;
  const double C11 = mat_.plate_modulus(), C12 = mat_.poisson * C11, C33 = 0.5 * (1 - mat_.poisson) * C11;
  // Per element, in parallel (each task writes only its elements' state and corner forces).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, quads_.size(), 64), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) {
      const auto& ids = quads_[e];
      const QuadFrame fr = quad_frame(corners(x_, ids));
      // Eq. (41): local nodal velocities; eq. (40): centre strain rate. v^{n-1/2} is evaluated on
      // the mid-step geometry x^{n-1/2} = x^n - h^{n-1/2}/2 v^{n-1/2} (second-order consistent rate).
      std::array<Vec3, 4> xh;
      for (int k = 0; k < 4; ++k) xh[k] = x_[ids[k]] - 0.5 * h_last * v_[ids[k]];
      const QuadFrame frh = quad_frame(xh);
      std::array<Vec3, 4> vl;
      for (int k = 0; k < 4; ++k) vl[k] = frh.q.transpose() * v_[ids[k]];
      double dxx = 0, dyy = 0, gxy = 0;
      Vec3 qdot = Vec3::Zero();
      for (int k = 0; k < 4; ++k) {
        dxx += frh.b1[k] * vl[k][0];
        dyy += frh.b2[k] * vl[k][1];
        gxy += frh.b2[k] * vl[k][0] + frh.b1[k] * vl[k][1];  // engineering shear rate 2 D_xy
        qdot += frh.gamma[k] * vl[k];
      }
      // Plane-stress elastic law in the co-rotational frame (no objective rate needed there).
      auto& s = stress_[e];
      s[0] += h_last * (C11 * dxx + C12 * dyy);
      s[1] += h_last * (C12 * dxx + C11 * dyy);
      s[2] += h_last * (C33 * gxy);
      // Flanagan-Belytschko stiffness hourglass forces, accumulated in the element frame.
      const double k = mat_.hourglass * hg_k_[e], kn = mat_.hourglass_normal * hg_k_[e];
      Vec3& Q = hg_force_[e];
      Q[0] += h_last * k * qdot[0];
      Q[1] += h_last * k * qdot[1];
      Q[2] += h_last * kn * qdot[2];
      // Eqs. (42)-(45): f_int = -q f_hat with f_hat = V (B sigma), plus hourglass -Q gamma_K.
      const double V = fr.area * mat_.thickness;
      for (int kk = 0; kk < 4; ++kk) {
        const Vec3 fl(V * (fr.b1[kk] * s[0] + fr.b2[kk] * s[2]), V * (fr.b2[kk] * s[1] + fr.b1[kk] * s[2]), 0.0);
        corner_force_[4 * e + kk] = -(fr.q * (fl + fr.gamma[kk] * Q));
      }
      pressure_force_[e] = 0.25 * pressure_ * fr.area_vector;
    }
  });
  // Per node: external part, then the corner forces of its elements in ascending element order
  // (the order of a serial element loop, so the sums do not depend on the thread count).
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 256), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i != r.end(); ++i) {
      f_ext_[i] = mass_[i] * gravity_ - damping_ * mass_[i] * v_[i];
      f_[i] = f_ext_[i];
      for (int a = node_start_[i]; a < node_start_[i + 1]; ++a) {
        const int e = node_corner_[a] / 4;
        f_[i] += corner_force_[node_corner_[a]];
        if (pressure_ != 0) {
          f_[i] += pressure_force_[e];
          f_ext_[i] += pressure_force_[e];
        }
      }
      for (int a = 0; a < 3; ++a)
        if (fixed_[i][a]) f_[i][a] = 0;
    }
  });
}

void Membrane::trial_velocities(double dt_step) {
  if (dt_step != h_step_) throw std::invalid_argument("membrane: trial_velocities got another step than compute_forces");
  const double h = h_n_;  // h^n of eq. (46), set by compute_forces
  for (int i = 0; i < num_nodes(); ++i) {
    const Vec3 v_old = v_[i];
    v_[i] += h * f_[i] / mass_[i];  // eq. (46)
    for (int a = 0; a < 3; ++a)
      if (fixed_[i][a]) v_[i][a] = 0;
    // Work of the external and damping forces over the step (midpoint velocity at t^n).
    const Vec3 vm = 0.5 * (v_old + v_[i]);
    const Vec3 fd = -damping_ * mass_[i] * v_old;
    ext_work_ += h * (f_ext_[i] - fd).dot(vm);
    damp_loss_ -= h * fd.dot(vm);
  }
}

void Membrane::update_positions(double h) {
  if (h != h_step_) throw std::invalid_argument("membrane: update_positions got another step than compute_forces");
  for (int i = 0; i < num_nodes(); ++i) {
    x_[i] += h * v_[i];  // eq. (47)
    if (!x_[i].allFinite() || !v_[i].allFinite()) {
      std::ostringstream msg;
      msg << "membrane: node " << i << " became non-finite; the time step is probably above the critical step";
      throw std::runtime_error(msg.str());
    }
  }
  h_prev_ = h;
}

void Membrane::step(double h) {
  compute_forces(h);
  trial_velocities(h);
  update_positions(h);
}

Mat3 Membrane::global_stress(int e) const {
  const QuadFrame fr = quad_frame(corners(x_, quads_[e]));
  Mat3 sl = Mat3::Zero();
  sl(0, 0) = stress_[e][0];
  sl(1, 1) = stress_[e][1];
  sl(0, 1) = sl(1, 0) = stress_[e][2];
  return fr.q * sl * fr.q.transpose();
}

std::vector<Vec3> Membrane::node_normals() const {
  std::vector<Vec3> nrm;
  node_normals(nrm);
  return nrm;
}

void Membrane::node_normals(std::vector<Vec3>& nrm) const {
  nrm.assign(x_.size(), Vec3::Zero());
  for (const auto& q : quads_) {
    const auto X = corners(x_, q);
    const Vec3 S = 0.5 * (X[2] - X[0]).cross(X[3] - X[1]);
    for (int id : q) nrm[id] += 0.25 * S;
  }
}

MembraneEnergies Membrane::energies() const {
  MembraneEnergies en;
  for (int i = 0; i < num_nodes(); ++i) en.kinetic += 0.5 * mass_[i] * v_[i].squaredNorm();
  const double E = mat_.youngs, nu = mat_.poisson, G = E / (2 * (1 + nu));
  for (std::size_t e = 0; e < quads_.size(); ++e) {
    const auto X = corners(x_, quads_[e]);
    const double V = 0.5 * (X[2] - X[0]).cross(X[3] - X[1]).norm() * mat_.thickness;
    const auto& s = stress_[e];
    const double exx = (s[0] - nu * s[1]) / E, eyy = (s[1] - nu * s[0]) / E, gxy = s[2] / G;
    en.strain += 0.5 * (s[0] * exx + s[1] * eyy + s[2] * gxy) * V;
    const double k = mat_.hourglass * hg_k_[e], kn = mat_.hourglass_normal * hg_k_[e];
    const Vec3& Q = hg_force_[e];
    if (k > 0) en.hourglass += 0.5 * (Q[0] * Q[0] + Q[1] * Q[1]) / k;
    if (kn > 0) en.hourglass += 0.5 * Q[2] * Q[2] / kn;
  }
  en.external_work = ext_work_;
  en.damping_loss = damp_loss_;
  return en;
}

Vec3 Membrane::total_momentum() const {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < num_nodes(); ++i) p += mass_[i] * v_[i];
  return p;
}

}  // namespace tetfsi::membrane
