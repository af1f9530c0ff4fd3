#include "fluid/liquid/cut_tet.hpp"

#include <Eigen/Dense>
#include <utility>

namespace tetfsi::fluid {
namespace {

/// Vertex k of the reference tet (node 0 at the origin, node k at the k-th unit vector): points of
/// the tet in these coordinates make volume fractions plain determinants.
Eigen::Vector3d reference_vertex(int k) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  if (k > 0) v[k - 1] = 1.0;
  return v;
}

Eigen::Vector3d reference_crossing(int a, int b, const std::array<double, 4>& phi) {
  const double theta = crossing_fraction(phi[a], phi[b]);
  return (1.0 - theta) * reference_vertex(a) + theta * reference_vertex(b);
}

double fraction_of(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                   const Eigen::Vector3d& p3) {
  Eigen::Matrix3d m;
  m << p1 - p0, p2 - p0, p3 - p0;
  return std::abs(m.determinant());
}

/// Volume fraction of the triangular prism (a0 a1 a2 | b0 b1 b2) whose faces are planar, split into
/// the three tets (a0 a1 a2 b0), (a1 a2 b0 b1), (a2 b0 b1 b2).
double prism_fraction(const std::array<Eigen::Vector3d, 3>& a, const std::array<Eigen::Vector3d, 3>& b) {
  return fraction_of(a[0], a[1], a[2], b[0]) + fraction_of(a[1], a[2], b[0], b[1]) +
         fraction_of(a[2], b[0], b[1], b[2]);
}

/// Volume fraction and first moment (fraction times centroid) of a part of the reference tet,
/// built from sub-tets.
struct ReferencePart {
  double fraction = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  void add(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2, const Eigen::Vector3d& p3,
           double sign = 1.0) {
    const double f = fraction_of(p0, p1, p2, p3);
    fraction += sign * f;
    moment += sign * f * (p0 + p1 + p2 + p3) / 4.0;
  }
};

/// Faces of a tet as local vertex triples (face f is opposite vertex f).
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// Adds the exact integral of psi phi_a over a sub-triangle S of a face, per unit face area:
/// `fraction` = A_S / A_F, `bary[j]` the face barycentric coordinates of S's vertex j, `psi[j]`
/// the hat's value there (see wet_face_mass).
void add_sub_triangle(double fraction, const std::array<Eigen::Vector3d, 3>& bary, const Eigen::Vector3d& psi,
                      std::array<double, 3>& row) {
  const Eigen::Vector3d sum_bary = bary[0] + bary[1] + bary[2];
  for (int a = 0; a < 3; ++a) {
    double s = 0.0;
    for (int j = 0; j < 3; ++j) s += psi[j] * bary[j][a];
    row[a] += fraction / 12.0 * (s + psi.sum() * sum_bary[a]);
  }
}

Eigen::Vector3d unit(int k) { return Eigen::Vector3d::Unit(k); }

}  // namespace

std::array<std::array<double, 3>, 3> wet_face_mass(const std::array<double, 3>& phi) {
  std::array<std::array<double, 3>, 3> m{};
  int liquid[3], air[3], nl = 0, na = 0;
  for (int k = 0; k < 3; ++k) (phi[k] < 0.0 ? liquid[nl++] : air[na++]) = k;
  if (nl == 3) {
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) m[k][a] = (k == a ? 2.0 : 1.0) / 12.0;
    return m;
  }
  const auto crossing = [&](int a, int b) {  // face barycentric coordinates of X_ab
    const double theta = crossing_fraction(phi[a], phi[b]);
    return Eigen::Vector3d((1.0 - theta) * unit(a) + theta * unit(b));
  };
  if (nl == 1) {  // (k, X_kp, X_kq), area fraction theta_kp theta_kq; psi_k = 1 at k only
    const int k = liquid[0], p = air[0], q = air[1];
    const double fraction = crossing_fraction(phi[k], phi[p]) * crossing_fraction(phi[k], phi[q]);
    add_sub_triangle(fraction, {unit(k), crossing(k, p), crossing(k, q)}, Eigen::Vector3d(1, 0, 0), m[k]);
  } else if (nl == 2) {  // the quad (i, j, X_jq, X_iq): the mean of its splits along i-X_jq and j-X_iq (cut_tet)
    const int q = air[0];
    for (const auto& [i, j] : {std::pair{liquid[0], liquid[1]}, std::pair{liquid[1], liquid[0]}}) {
      const double tj = crossing_fraction(phi[j], phi[q]), ti = crossing_fraction(phi[i], phi[q]);
      const std::array<Eigen::Vector3d, 3> first{unit(i), unit(j), crossing(j, q)};
      add_sub_triangle(0.5 * tj, first, Eigen::Vector3d(1, 0, 0), m[i]);
      add_sub_triangle(0.5 * tj, first, Eigen::Vector3d(0, 1, 0), m[j]);
      add_sub_triangle(0.5 * ti * (1.0 - tj), {unit(i), crossing(j, q), crossing(i, q)}, Eigen::Vector3d(1, 0, 0), m[i]);
    }
  }
  return m;
}

double liquid_fraction(const std::array<double, 4>& phi) {
  int liquid[4], air[4], nl = 0, na = 0;
  for (int k = 0; k < 4; ++k) (phi[k] < 0.0 ? liquid[nl++] : air[na++]) = k;
  if (nl == 0) return 0.0;
  if (nl == 4) return 1.0;
  if (nl == 1) {  // a corner of liquid at liquid[0]: the edges from it are cut at theta
    double f = 1.0;
    for (int j = 0; j < 3; ++j) f *= crossing_fraction(phi[liquid[0]], phi[air[j]]);
    return f;
  }
  if (nl == 3) {  // everything but a corner of air at air[0]
    double f = 1.0;
    for (int j = 0; j < 3; ++j) f *= 1.0 - crossing_fraction(phi[liquid[j]], phi[air[0]]);
    return 1.0 - f;
  }
  // Two liquid nodes a, b and two air nodes c, d: the prism (a, X_ac, X_ad | b, X_bc, X_bd); its
  // faces lie on the tet faces abc, abd and on the (planar) surface.
  const int a = liquid[0], b = liquid[1], c = air[0], d = air[1];
  return prism_fraction({reference_vertex(a), reference_crossing(a, c, phi), reference_crossing(a, d, phi)},
                        {reference_vertex(b), reference_crossing(b, c, phi), reference_crossing(b, d, phi)});
}

Eigen::Vector3d liquid_first_moment(const std::array<Eigen::Vector3d, 4>& x, const std::array<double, 4>& phi) {
  int liquid[4], air[4], nl = 0, na = 0;
  for (int k = 0; k < 4; ++k) (phi[k] < 0.0 ? liquid[nl++] : air[na++]) = k;
  ReferencePart part;
  const auto v = reference_vertex;
  if (nl == 4) {
    part.add(v(0), v(1), v(2), v(3));
  } else if (nl == 1) {
    const int a = liquid[0];
    part.add(v(a), reference_crossing(a, air[0], phi), reference_crossing(a, air[1], phi),
             reference_crossing(a, air[2], phi));
  } else if (nl == 3) {  // the tet less its corner of air
    const int c = air[0];
    part.add(v(0), v(1), v(2), v(3));
    part.add(v(c), reference_crossing(liquid[0], c, phi), reference_crossing(liquid[1], c, phi),
             reference_crossing(liquid[2], c, phi), -1.0);
  } else if (nl == 2) {  // the prism of liquid_fraction, as its three tets
    const int a = liquid[0], b = liquid[1], c = air[0], d = air[1];
    const Eigen::Vector3d a0 = v(a), a1 = reference_crossing(a, c, phi), a2 = reference_crossing(a, d, phi);
    const Eigen::Vector3d b0 = v(b), b1 = reference_crossing(b, c, phi), b2 = reference_crossing(b, d, phi);
    part.add(a0, a1, a2, b0);
    part.add(a1, a2, b0, b1);
    part.add(a2, b0, b1, b2);
  }
  // x(xi) = x0 + J xi maps the reference tet (volume 1/6) onto the tet (volume V): int x dV = V (f x0 + J m).
  Eigen::Matrix3d J;
  J << x[1] - x[0], x[2] - x[0], x[3] - x[0];
  const double volume = J.determinant() / 6.0;
  return volume * (part.fraction * x[0] + J * part.moment);
}

CutTet cut_tet(const std::array<Eigen::Vector3d, 4>& x, const std::array<double, 4>& phi) {
  CutTet c;
  for (auto& a : c.wet_moment) a.setZero();
  const double volume = (x[1] - x[0]).cross(x[2] - x[0]).dot(x[3] - x[0]) / 6.0;
  c.liquid_volume = volume * liquid_fraction(phi);
  c.first_moment = liquid_first_moment(x, phi);
  for (int f = 0; f < 4; ++f) {
    // Outward area vector of the face (positively oriented tet: kFace is counter-clockwise from outside).
    const int i0 = kFace[f][0], i1 = kFace[f][1], i2 = kFace[f][2];
    const Eigen::Vector3d s = 0.5 * (x[i1] - x[i0]).cross(x[i2] - x[i0]);
    int liquid[3], air[3], nl = 0, na = 0;
    for (int k : {i0, i1, i2}) (phi[k] < 0.0 ? liquid[nl++] : air[na++]) = k;
    if (nl == 0) continue;
    if (nl == 3) {  // fully wet: int psi_k dA = A_F / 3
      for (int k : {i0, i1, i2}) c.wet_moment[k] += s / 3.0;
      continue;
    }
    if (nl == 1) {  // wet triangle (m, X_mp, X_mq): area fraction theta_mp theta_mq
      const int m = liquid[0];
      const double w = crossing_fraction(phi[m], phi[air[0]]) * crossing_fraction(phi[m], phi[air[1]]);
      c.wet_moment[m] += (w / 3.0) * s;
      continue;
    }
    // Two liquid nodes m, n and air q: the wet quad (m, n, X_nq, X_mq), the mean of its two splits.
    // Along m-X_nq: (m, n, X_nq), area fraction theta_nq, and (m, X_nq, X_mq), theta_mq (1 -
    // theta_nq), so int psi_m dA = A (tn + tm (1 - tn)) / 3 and int psi_n dA = A tn / 3; along
    // n-X_mq the same with m and n exchanged.
    const int m = liquid[0], n = liquid[1], q = air[0];
    const double tn = crossing_fraction(phi[n], phi[q]), tm = crossing_fraction(phi[m], phi[q]);
    c.wet_moment[m] += ((tn + 2.0 * tm - tm * tn) / 6.0) * s;
    c.wet_moment[n] += ((tm + 2.0 * tn - tm * tn) / 6.0) * s;
  }
  return c;
}

}  // namespace tetfsi::fluid
