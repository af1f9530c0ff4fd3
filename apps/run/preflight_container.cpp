#include "apps/run/preflight_container.hpp"

#include <fmt/format.h>

#include "apps/run/container.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/scene_values.hpp"
#include "mesh/surface_checks.hpp"

namespace tetfsi::run {
namespace {

/// The placed file of a `mesh` container inside the domain box and at least an edge length
/// across in every direction; false (reported in `issues`) if not.
bool mesh_container_fits(const scene::Json& domain, const mesh::SurfaceMesh& container, double edge,
                         std::vector<scene::Issue>& issues) {
  Eigen::Vector3d lo = container.vertices.front(), hi = lo;
  for (const auto& v : container.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Eigen::Vector3d dlo = vec3(domain["lo"]), dhi = vec3(domain["hi"]);
  const double slack = 1e-6 * (dhi - dlo).norm();  // assimp reads files in single precision
  if ((lo.array() < dlo.array() - slack).any() || (hi.array() > dhi.array() + slack).any()) {
    issues.push_back({"/domain/container",
                      fmt::format("the container's surface (bounding box [{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, "
                                  "{:.4g}] m) reaches outside the domain box; enlarge /domain or move the container "
                                  "(/domain/container/translation)", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z())});
    return false;
  }
  if ((hi - lo).minCoeff() < edge) {
    issues.push_back({"/domain/container",
                      fmt::format("the container's surface is {:.4g} m across at its thinnest, below mesh.edge_length "
                                  "({:.4g} m): the mesh could not resolve it; refine the mesh or scale the container "
                                  "(/domain/container/unit_scale)", (hi - lo).minCoeff(), edge)});
    return false;
  }
  return true;
}

}  // namespace

std::vector<scene::Issue> container_issues(const scene::Json& js, const std::vector<ContainedSolid>& solids) {
  std::vector<scene::Issue> issues;
  const auto& domain = js.at("domain");
  if (!domain.contains("container")) return issues;
  const auto& c = domain["container"];
  if (c.at("type") == "box") return issues;
  const double edge = js.at("mesh").at("edge_length").get<double>();
  for (const char* k : {"radius", "length"})
    if (c.contains(k) && c[k].get<double>() < edge)
      issues.push_back({fmt::format("/domain/container/{}", k),
                        fmt::format("the container's {} ({:.4g} m) is below mesh.edge_length ({:.4g} m): the mesh "
                                    "could not resolve it; refine the mesh or enlarge the container",
                                    k, c[k].get<double>(), edge)});
  mesh::SurfaceMesh container;
  try {
    container = container_surface(domain);
  } catch (const InputError& e) {
    issues.push_back({"/domain/container/file", e.what()});
    return issues;
  }
  if (c.at("type") == "mesh" && !mesh_container_fits(domain, container, edge, issues)) return issues;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    if (!solids[i].surface || mesh::surface_inside(*solids[i].surface, container)) continue;
    issues.push_back({fmt::format("/solids/{}/placement", i),
                      fmt::format("solid '{}' is not strictly inside the {} container /domain/container (the surfaces "
                                  "meet or the solid lies outside)", solids[i].name, c.at("type").get<std::string>())});
  }
  return issues;
}

}  // namespace tetfsi::run
