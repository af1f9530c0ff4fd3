#include "apps/run/preflight_volumes.hpp"

#include <cmath>

#include <fmt/format.h>

#include "apps/run/preflight.hpp"
#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

double volume_voxels(const scene::Json& js, double default_voxel_size, std::vector<scene::Issue>& issues) {
  if (!js.contains("domain")) return 0;
  const auto& exp = js.at("export");
  const bool given = exp.contains("voxel_size");
  const double h = given ? exp["voxel_size"].get<double>() : default_voxel_size;
  const Eigen::Vector3d size = vec3(js["domain"]["hi"]) - vec3(js["domain"]["lo"]);
  double voxels = 1;
  for (int a = 0; a < 3; ++a) voxels *= std::ceil(size[a] / h) + 2;  // as voxel_range, at most
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
