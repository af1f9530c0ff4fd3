#include "apps/run/fluid_probe.hpp"

#include <limits>

#include "apps/run/scene_values.hpp"
#include "fluid/advection/point_locator.hpp"

namespace tetfsi::run {

double fluid_point_value(const fluid::FluidSolver& fluid, const scene::Json& probe) {
  const auto& fm = fluid.mesh();
  const fluid::PointLocator locator(fm);
  const auto loc = locator.locate(vec3(probe.at("point")), 0);
  if (!loc.inside) return std::numeric_limits<double>::quiet_NaN();
  const auto q = probe.at("quantity").get<std::string>();
  const auto& fl = fluid.fields();
  if (q == "pressure") {
    double v = 0;
    for (int k = 0; k < 4; ++k) v += loc.bary[k] * fluid.pressure()[fm.tets[loc.tet][k]];
    return v;
  }
  if (q == "smoke") return fl.smoke[loc.tet];
  if (q == "temperature") return fl.temperature[loc.tet];
  const Eigen::Vector3d u = fl.velocity[loc.tet];
  if (q == "speed") return u.norm();
  return u[q.back() - 'x'];
}

}  // namespace tetfsi::run
