#include "apps/run/preflight_volumes.hpp"

#include <cmath>

#include <fmt/format.h>

#include "apps/run/preflight.hpp"
#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

namespace {

/// Voxels of edge h over the domain box, as voxel_range counts them at most.
double domain_voxels(const scene::Json& js, double h) {
  const Eigen::Vector3d size = vec3(js["domain"]["hi"]) - vec3(js["domain"]["lo"]);
  double voxels = 1;
  for (int a = 0; a < 3; ++a) voxels *= std::ceil(size[a] / h) + 2;
  return voxels;
}

}  // namespace

void liquid_surface_voxels(const scene::Json& js, std::vector<scene::Issue>& issues) {
  if (!js.contains("domain")) return;
  const auto surface = js.at("export").value("liquid_surface", scene::Json::object());
  if (surface.value("type", "smooth") != "smooth") return;
  double h = 0;
  std::string key = "/export/liquid_surface/voxel_size";
  if (surface.contains("voxel_size")) {
    h = surface["voxel_size"].get<double>();
  } else if (surface.contains("smoothing") && surface["smoothing"].get<double>() > 0) {
    h = 0.25 * surface["smoothing"].get<double>();
    key = "/export/liquid_surface/smoothing";
  }
  if (!(h > 0)) return;
  const double voxels = domain_voxels(js, h);
  if (!(voxels <= default_max_voxels()))
    issues.push_back({key, fmt::format("the smooth liquid surface would sample up to {:.3g} voxels of {:.4g} m over the "
                                       "domain box (about {} of memory), more than the limit of {:.3g} voxels (a "
                                       "quarter of this machine's memory at {:g} bytes per voxel): raise {}",
                                       voxels, h, format_bytes(voxels * kBytesPerVoxel), default_max_voxels(),
                                       kBytesPerVoxel, key)});
}

double volume_voxels(const scene::Json& js, double default_voxel_size, std::vector<scene::Issue>& issues) {
  if (!js.contains("domain")) return 0;
  const auto& exp = js.at("export");
  const bool given = exp.contains("voxel_size");
  const double h = given ? exp["voxel_size"].get<double>() : default_voxel_size;
  const double voxels = domain_voxels(js, h);
  if (!(voxels <= default_max_voxels()))
    issues.push_back({"/export/voxel_size",
                      fmt::format("the volumes would have about {:.3g} voxels over the domain box at a voxel size of "
                                  "{:.4g} m{} (about {} of memory), more than the limit of {:.3g} voxels (a quarter "
                                  "of this machine's memory at {:g} bytes per voxel): {} /export/voxel_size",
                                  voxels, h, given ? "" : " (half of the finest edge length)",
                                  format_bytes(voxels * kBytesPerVoxel), default_max_voxels(), kBytesPerVoxel,
                                  given ? "raise" : "set a larger")});
  return voxels;
}

}  // namespace tetfsi::run
