#include "fluid/stable_step.hpp"

#include <algorithm>
#include <cmath>

namespace tetfsi::fluid {

double cfl_step(const FluidSolver& fluid, double courant, double dx, double solid_speed, double h_max,
                bool free_fall) {
  double u_max = solid_speed;
  for (const auto& v : fluid.fields().velocity) u_max = std::max(u_max, v.norm());
  if (free_fall && fluid.has_free_surface()) u_max = std::max(u_max, std::sqrt(fluid.params().gravity.norm() * dx));
  return u_max > 0 ? std::min(h_max, courant * dx / u_max) : h_max;
}

}  // namespace tetfsi::fluid
