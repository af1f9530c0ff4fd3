/// @file quality.cpp
#include "mesh/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace tetfsi::mesh {

namespace {

/// Unit normal of face k (the face opposite vertex k) of tet (a, b, c, d), oriented away from vertex
/// k, so both normals of an edge point out of the tet whatever the tet's orientation; zero for a
/// face of zero area. Shared by dihedral_angles_deg and min_dihedral_check (the same cosines).
std::array<Eigen::Vector3d, 4> outward_face_normals(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                    const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const std::array<const Eigen::Vector3d*, 4> p{&a, &b, &c, &d};
  std::array<Eigen::Vector3d, 4> n;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& p0 = *p[(k + 1) % 4];
    Eigen::Vector3d m = (*p[(k + 2) % 4] - p0).cross(*p[(k + 3) % 4] - p0);
    if (m.dot(*p[k] - p0) > 0.0) m = -m;
    const double len = m.norm();
    n[k] = len > 0.0 ? Eigen::Vector3d(m / len) : Eigen::Vector3d::Zero();
  }
  return n;
}

}  // namespace

std::array<double, 6> dihedral_angles_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  const std::array<Eigen::Vector3d, 4> n = outward_face_normals(a, b, c, d);
  // Edge (i, j) is shared by the faces opposite the two other vertices.
  static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  std::array<double, 6> out{};
  for (int e = 0; e < 6; ++e) {
    int f[2], m = 0;
    for (int k = 0; k < 4; ++k)
      if (k != kEdges[e][0] && k != kEdges[e][1]) f[m++] = k;
    const double cosine = std::clamp(-n[f[0]].dot(n[f[1]]), -1.0, 1.0);
    out[e] = std::acos(cosine) * 180.0 / M_PI;
  }
  return out;
}

double radius_edge_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& d) {
  // Circumcentre x solves 2 (p_i - a) . x' = |p_i - a|^2 for i = b, c, d, with x' = x - a.
  Eigen::Matrix3d A;
  A.row(0) = 2.0 * (b - a);
  A.row(1) = 2.0 * (c - a);
  A.row(2) = 2.0 * (d - a);
  const Eigen::Vector3d rhs((b - a).squaredNorm(), (c - a).squaredNorm(), (d - a).squaredNorm());
  const double det = A.determinant();
  if (det == 0.0) return std::numeric_limits<double>::infinity();
  const double radius = (A.inverse() * rhs).norm();
  const double lmin = std::sqrt(std::min({(b - a).squaredNorm(), (c - a).squaredNorm(), (d - a).squaredNorm(),
                                          (c - b).squaredNorm(), (d - b).squaredNorm(), (d - c).squaredNorm()}));
  return lmin > 0.0 ? radius / lmin : std::numeric_limits<double>::infinity();
}

double relative_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       const Eigen::Vector3d& d) {
  const double lmax = std::sqrt(std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (d - a).squaredNorm(),
                                          (c - b).squaredNorm(), (d - b).squaredNorm(), (d - c).squaredNorm()}));
  return lmax > 0.0 ? 6.0 * signed_volume(a, b, c, d) / (lmax * lmax * lmax) : 0.0;
}

namespace {

/// Largest −n_i·n_j over the six edges of a tet with positive volume (see dihedral_angles_deg).
double max_dihedral_cosine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& d) {
  const std::array<Eigen::Vector3d, 4> n = outward_face_normals(a, b, c, d);
  // Edge (i, j) is shared by the faces opposite the other two vertices: pairs of faces (k, l).
  static constexpr int kFacePairs[6][2] = {{2, 3}, {1, 3}, {1, 2}, {0, 3}, {0, 2}, {0, 1}};
  double largest = -1.0;
  for (const auto& f : kFacePairs) largest = std::max(largest, std::clamp(-n[f[0]].dot(n[f[1]]), -1.0, 1.0));
  return largest;
}

QualityReport report(const TetMesh& mesh, bool filter, int label) {
  QualityReport q;
  q.num_vertices = mesh.num_vertices();
  q.min_dihedral_deg = 180.0;
  q.max_dihedral_deg = 0.0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int sub = mesh.subdomain.empty() ? 1 : mesh.subdomain[t];
    if (filter && sub != label) continue;
    ++q.tets_per_subdomain[sub];
    ++q.num_tets;
    const auto& v = mesh.tets[t];
    const auto &a = mesh.vertices[v[0]], &b = mesh.vertices[v[1]], &c = mesh.vertices[v[2]],
               &d = mesh.vertices[v[3]];
    const double vol = relative_volume(a, b, c, d);
    if (std::abs(vol) <= 6e-12) {
      ++q.degenerate;
      continue;
    }
    if (vol < 0.0) {
      ++q.inverted;
      continue;
    }
    for (double angle : dihedral_angles_deg(a, b, c, d)) {
      q.min_dihedral_deg = std::min(q.min_dihedral_deg, angle);
      q.max_dihedral_deg = std::max(q.max_dihedral_deg, angle);
    }
    q.max_radius_edge = std::max(q.max_radius_edge, radius_edge_ratio(a, b, c, d));
  }
  if (q.num_tets == q.inverted + q.degenerate) q.min_dihedral_deg = 0.0;
  return q;
}

}  // namespace

AngleCheck min_dihedral_check(const TetMesh& mesh, int subdomain) {
  struct Partial {
    double max_cosine = -2.0;  // below any cosine: no valid tet yet
    int spoiled = 0;
  };
  const Partial total = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, mesh.num_tets(), 4096), Partial{},
      [&](const tbb::blocked_range<int>& range, Partial part) {
        for (int t = range.begin(); t < range.end(); ++t) {
          if ((mesh.subdomain.empty() ? 1 : mesh.subdomain[t]) != subdomain) continue;
          const auto& v = mesh.tets[t];
          const auto &a = mesh.vertices[v[0]], &b = mesh.vertices[v[1]], &c = mesh.vertices[v[2]],
                     &d = mesh.vertices[v[3]];
          if (relative_volume(a, b, c, d) <= 6e-12) {
            ++part.spoiled;
            continue;
          }
          part.max_cosine = std::max(part.max_cosine, max_dihedral_cosine(a, b, c, d));
        }
        return part;
      },
      // max and integer sums are exact in any order: the result does not depend on the split.
      [](Partial x, const Partial& y) {
        x.max_cosine = std::max(x.max_cosine, y.max_cosine);
        x.spoiled += y.spoiled;
        return x;
      });
  AngleCheck check;
  check.flat_or_inverted = total.spoiled;
  check.min_dihedral_deg = total.max_cosine < -1.5 ? 0.0 : std::acos(total.max_cosine) * 180.0 / M_PI;
  return check;
}

double mean_edge_length(const TetMesh& mesh, int subdomain) {
  double sum = 0.0;
  long count = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (!mesh.subdomain.empty() && mesh.subdomain[t] != subdomain) continue;
    const auto& v = mesh.tets[t];
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        sum += (mesh.vertices[v[i]] - mesh.vertices[v[j]]).norm();
        ++count;
      }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

QualityReport quality_report(const TetMesh& mesh) { return report(mesh, false, 0); }

QualityReport quality_report(const TetMesh& mesh, int subdomain) { return report(mesh, true, subdomain); }

std::string QualityReport::summary() const {
  std::ostringstream s;
  s.precision(4);
  s << num_tets << " tets (";
  bool first = true;
  for (const auto& [label, count] : tets_per_subdomain) {
    s << (first ? "" : ", ") << "subdomain " << label << ": " << count;
    first = false;
  }
  s << "), " << num_vertices << " vertices, dihedral [" << min_dihedral_deg << ", " << max_dihedral_deg
    << "] deg, max radius-edge " << max_radius_edge << ", " << inverted << " inverted, " << degenerate
    << " degenerate";
  return s.str();
}

}  // namespace tetfsi::mesh
