#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>

#include "fluid/io/vdb_fields.hpp"

namespace tetfsi::fluid::vdb {
namespace {

using openvdb::Coord;

/// The 12 edges of a voxel cell as pairs of corners; corner q = (a, b, e) has bits a + 2 b + 4 e.
constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                               {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

Eigen::Vector3d corner(int q) { return {double(q & 1), double(q >> 1 & 1), double(q >> 2 & 1)}; }

/// psi, phi_s - delta and D at the corners of the cell with lowest corner c0, and the boundary
/// triangle nearest each corner (-1: none).
struct CellValues {
  Coord c0;
  float psi[8], f[8], d[8];
  int tri[8];
};

CellValues read_cell(const Fields& g, const openvdb::FloatGrid& psi, const Coord& c0, float delta) {
  CellValues v;
  v.c0 = c0;
  auto sa = psi.getConstAccessor();
  auto pa = g.phi->getConstAccessor();
  auto da = g.wall->getConstAccessor();
  auto ka = g.known->getConstAccessor();
  auto na = g.nearest->getConstAccessor();
  for (int q = 0; q < 8; ++q) {
    const Coord c = c0.offsetBy(q & 1, q >> 1 & 1, q >> 2 & 1);
    v.psi[q] = sa.getValue(c);
    v.f[q] = pa.getValue(c) - delta;
    v.d[q] = ka.isValueOn(c) ? da.getValue(c) : g.band;
    v.tri[q] = na.isValueOn(c) ? na.getValue(c) : -1;
  }
  return v;
}

/// Trilinear interpolant of corner values at t in [0, 1]^3 (index units); its gradient if asked.
double trilinear(const float v[8], const Eigen::Vector3d& t, Eigen::Vector3d* grad = nullptr) {
  double value = 0;
  if (grad) grad->setZero();
  for (int q = 0; q < 8; ++q) {
    const Eigen::Vector3d c = corner(q);
    const Eigen::Vector3d w = (c.array() * t.array() + (1 - c.array()) * (1 - t.array())).matrix();
    value += v[q] * w.x() * w.y() * w.z();
    if (grad) {
      const Eigen::Vector3d s = 2 * c.array() - 1;
      *grad += v[q] * Eigen::Vector3d(s.x() * w.y() * w.z(), w.x() * s.y() * w.z(), w.x() * w.y() * s.z());
    }
  }
  return value;
}

/// The boundary triangle, among those nearest the cell's corners, whose plane passes nearest x
/// (cell coordinates); -1 if the corners have none.
int wall_triangle(const Fields& g, const CellValues& v, const Eigen::Vector3d& x_cell) {
  const Eigen::Vector3d x = x_cell + Eigen::Vector3d(v.c0.x(), v.c0.y(), v.c0.z());
  int best = -1;
  double best_distance = 0;
  for (int q = 0; q < 8; ++q) {
    const int t = v.tri[q];
    if (t < 0 || t >= static_cast<int>(g.wall_normal.size())) continue;
    const double distance = std::abs(g.wall_normal[t].dot(x - g.wall_point[t]));
    if (best < 0 || distance < best_distance) best = t, best_distance = distance;
  }
  return best;
}

/// A zero crossing of psi on a cell edge, in cell coordinates: where volumeToMesh puts it (the
/// linear interpolant of psi's values vanishes), and the Hermite point and normal of the surface
/// that bounds the liquid there: the nearer to the liquid end of the zeros of f = phi_s - delta
/// (linear along the edge; normal: gradient of the trilinear f) and of D (the edge's intersection
/// with the plane of the nearest boundary triangle, exact for plane walls, where D itself, the
/// distance to the nearest of several walls, is not linear; without a triangle, D's linear zero
/// and the gradient of the trilinear D).
struct Crossing {
  Eigen::Vector3d mesher_point, x, n;
  bool wall;  ///< the wall (D) bounds the liquid at x
};

std::vector<Crossing> crossings(const Fields& g, const CellValues& v) {
  std::vector<Crossing> out;
  for (const auto& e : kEdges) {
    const double a = v.psi[e[0]], b = v.psi[e[1]];
    if ((a < 0) == (b < 0)) continue;
    const int in = a < 0 ? e[0] : e[1], outside = a < 0 ? e[1] : e[0];
    const Eigen::Vector3d p = corner(in), q = corner(outside);
    // Zeros of f and D from the liquid end (s = 0) towards the other (s = 1); 2 if none. One of
    // them is >= 0 at the other end, since psi is.
    auto zero = [](double from, double to) { return from < 0 && to >= 0 ? from / (from - to) : 2.0; };
    const double sf = zero(v.f[in], v.f[outside]);
    double sd = zero(v.d[in], v.d[outside]);
    const int t = sd <= 1 ? wall_triangle(g, v, p + sd * (q - p)) : -1;
    if (t >= 0) {  // onto the triangle's plane: n . (p + s (q - p) - a) = 0
      const Eigen::Vector3d& n = g.wall_normal[t];
      const Eigen::Vector3d a_cell = g.wall_point[t] - Eigen::Vector3d(v.c0.x(), v.c0.y(), v.c0.z());
      const double along = n.dot(q - p);
      if (std::abs(along) > 1e-9) sd = std::clamp(n.dot(a_cell - p) / along, 0.0, 1.0);
    }
    Crossing c;
    c.mesher_point = corner(e[0]) + (-a / (b - a)) * (corner(e[1]) - corner(e[0]));
    c.wall = sd < sf;
    c.x = p + std::min({sf, sd, 1.0}) * (q - p);
    if (c.wall && t >= 0) {
      c.n = g.wall_normal[t];
    } else {
      trilinear(c.wall ? v.d : v.f, c.x, &c.n);
      c.n.normalize();
    }
    out.push_back(c);
  }
  return out;
}

Eigen::Vector3d mean_point(const std::vector<Crossing>& cs, Eigen::Vector3d Crossing::*point) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const auto& c : cs) m += c.*point;
  return m / double(cs.size());
}

}  // namespace

void place_on_sharp_edges(const Fields& g, const openvdb::FloatGrid& psi, float delta, openvdb::Vec3s& p) {
  // The cell holding p; on a cell face (within round-off), the neighbour across it is a candidate too.
  const Eigen::Vector3d pd(p.x(), p.y(), p.z());
  std::vector<Coord> candidates{Coord(int(std::floor(pd.x())), int(std::floor(pd.y())), int(std::floor(pd.z())))};
  for (int a = 0; a < 3; ++a)
    if (std::abs(pd[a] - std::round(pd[a])) < 1e-4) {
      const std::size_t n = candidates.size();
      for (std::size_t k = 0; k < n; ++k) {
        Coord c = candidates[k];
        c[a] = int(std::round(pd[a])) - (c[a] == int(std::round(pd[a])) ? 1 : 0);
        candidates.push_back(c);
      }
    }
  for (const Coord& c0 : candidates) {
    const CellValues v = read_cell(g, psi, c0, delta);
    const std::vector<Crossing> cs = crossings(g, v);
    if (cs.empty()) continue;
    const Eigen::Vector3d origin(c0.x(), c0.y(), c0.z());
    if ((origin + mean_point(cs, &Crossing::mesher_point) - pd).norm() > 1e-3) continue;  // not p's cell, or several sheets
    const Eigen::Vector3d m = mean_point(cs, &Crossing::x);
    bool wall = false;
    for (const auto& c : cs) wall = wall || c.wall;
    if (!wall) {  // the free surface alone: the mean of its crossings
      const Eigen::Vector3d x = origin + m;
      p = openvdb::Vec3s(float(x.x()), float(x.y()), float(x.z()));
      return;
    }
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (const auto& c : cs) {
      if (!c.n.allFinite()) continue;
      A += c.n * c.n.transpose();
      rhs += c.n * c.n.dot(c.x - m);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
    const double largest = eig.eigenvalues().maxCoeff();
    Eigen::Vector3d x = m;
    for (int k = 0; k < 3; ++k) {
      const double lambda = eig.eigenvalues()[k];
      if (lambda > 0.01 * largest) x += eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(rhs) / lambda);
    }
    x = (origin + x.cwiseMax(0.0).cwiseMin(1.0)).eval();
    p = openvdb::Vec3s(float(x.x()), float(x.y()), float(x.z()));
    return;
  }
}

double wall_distance_at(const Fields& g, const openvdb::Vec3d& p) {
  const Coord c0(int(std::floor(p.x())), int(std::floor(p.y())), int(std::floor(p.z())));
  auto da = g.wall->getConstAccessor();
  auto ka = g.known->getConstAccessor();
  float d[8];
  for (int q = 0; q < 8; ++q) {
    const Coord c = c0.offsetBy(q & 1, q >> 1 & 1, q >> 2 & 1);
    d[q] = ka.isValueOn(c) ? da.getValue(c) : g.band;
  }
  return trilinear(d, Eigen::Vector3d(p.x() - c0.x(), p.y() - c0.y(), p.z() - c0.z()));
}

}  // namespace tetfsi::fluid::vdb
