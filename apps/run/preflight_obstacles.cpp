#include "apps/run/preflight_obstacles.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "apps/run/scene_values.hpp"
#include "apps/run/solid_params.hpp"

namespace tetfsi::run {

bool box_outside_solid(const mesh::SurfaceMesh& s, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  double solid_angle = 0;
  for (const auto& t : s.triangles) {
    const Eigen::Vector3d &p = s.vertices[t[0]], &q = s.vertices[t[1]], &r = s.vertices[t[2]];
    if ((p.cwiseMax(q).cwiseMax(r).array() >= lo.array()).all() && (p.cwiseMin(q).cwiseMin(r).array() <= hi.array()).all())
      return false;  // the surface may cross the box
    // Solid angle of the triangle seen from the centre: tan(omega / 2) = a.(b x c) / (|a||b||c| +
    // (a.b)|c| + (b.c)|a| + (c.a)|b|) (Van Oosterom & Strackee 1983, eq. 8).
    const Eigen::Vector3d a = p - centre, b = q - centre, c = r - centre;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    solid_angle += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return std::fabs(solid_angle) < 2 * M_PI;  // winding number 0 (outside), not 1 (inside)
}

std::vector<scene::Issue> obstacle_issues(const scene::Json& js, const std::string& runner,
                                          const std::vector<ContainedSolid>& solids) {
  std::vector<scene::Issue> issues;
  if (!js.contains("obstacles") || (runner != "solid" && runner != "hex" && runner != "coupled")) return issues;
  const auto& planes = js["obstacles"].at("planes");
  const auto& boxes = js["obstacles"].at("boxes");
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const auto& solid = js["solids"][i];
    if (!solids[i].surface || solid.at("motion").at("type") != "none" || is_static(solid)) continue;
    const auto& vertices = solids[i].surface->vertices;
    if (vertices.empty()) continue;
    Eigen::Vector3d lo = vertices.front(), hi = lo;
    for (const auto& v : vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double tol = 1e-6 * (hi - lo).norm();
    // depth(v) > 0: how far vertex v lies inside obstacle k.
    auto report = [&](const std::string& obstacle, const auto& depth) {
      std::size_t inside = 0;
      double deepest = 0;
      for (const auto& v : vertices) {
        const double d = depth(v);
        if (d > tol) ++inside, deepest = std::max(deepest, d);
      }
      if (inside == 0) return;
      issues.push_back({fmt::format("/solids/{}/placement", i),
                        fmt::format("solid '{}' starts inside the obstacle {}: {} of its {} surface vertices lie in it, "
                                    "the deepest {:.3g} m; move the solid to the obstacle's free side",
                                    solids[i].name, obstacle, inside, vertices.size(), deepest)});
    };
    for (std::size_t k = 0; k < planes.size(); ++k) {
      const Eigen::Vector3d p = vec3(planes[k].at("point")), n = vec3(planes[k].at("normal")).normalized();
      report(fmt::format("/obstacles/planes/{}", k), [&](const Eigen::Vector3d& v) { return -(v - p).dot(n); });
    }
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      const Eigen::Vector3d blo = vec3(boxes[k].at("lo")), bhi = vec3(boxes[k].at("hi"));
      report(fmt::format("/obstacles/boxes/{}", k),
             [&](const Eigen::Vector3d& v) { return std::min((v - blo).minCoeff(), (bhi - v).minCoeff()); });
    }
  }
  return issues;
}

}  // namespace tetfsi::run
