#include "apps/run/preflight_mpm.hpp"

#include <fmt/format.h>

#include <limits>

#include "apps/mpm/setup.hpp"

namespace tetfsi::run {

MpmStepBound mpm_step_bound(const scene::Json& js) {
  const auto& g = js.at("simulation").at("gravity");
  const auto setup = mpm_setup::build_setup(js.at("mpm"), mpm::Vec3(g[0].get<double>(), g[1].get<double>(), g[2].get<double>()));
  const auto model = mpm_setup::make_model(setup);
  MpmStepBound b{model->max_dt(), "/mpm/mpm_cfl", ""};
  const double mpm = model->mpm().critical_time_step();
  const double membrane = model->membrane().critical_time_step(setup.membrane_cfl);
  // The explicit viscous bound mpm_cfl rho dx^2 / (8 mu) of each viscous fluid body (solver_detail.hpp).
  double viscous = std::numeric_limits<double>::infinity();
  std::size_t viscous_body = 0;
  for (std::size_t i = 0; i < setup.materials.size(); ++i) {
    const auto& mat = setup.materials[i];
    if (mat.kind != mpm::Material::Kind::Fluid || !(mat.viscosity > 0)) continue;
    const double h = setup.options.cfl * mat.rho0 * setup.grid.dx * setup.grid.dx / (8 * mat.viscosity);
    if (h < viscous) viscous = h, viscous_body = i;
  }
  if (membrane <= mpm && membrane <= b.dt) {
    b.key = "/mpm/membrane_cfl";
    b.what = fmt::format("the membrane's critical step, membrane_cfl {:g} x min(L_e / c) (eq. 48)", setup.membrane_cfl);
  } else if (viscous <= mpm * (1 + 1e-9)) {
    b.key = fmt::format("/mpm/bodies/{}/material/viscosity", viscous_body);
    b.what = fmt::format("the explicit viscous step mpm_cfl rho dx^2 / (8 mu) of body '{}' (mpm_cfl {:g}, mu = {:g} "
                         "Pa s; /mpm/mpm_cfl scales it too)",
                         setup.bodies[viscous_body].name, setup.options.cfl, setup.materials[viscous_body].viscosity);
  } else if (mpm <= b.dt) {
    b.what = fmt::format("the particles' critical step, mpm_cfl {:g} x dx / (c + |v|) (eq. 21)", setup.options.cfl);
  } else {
    b.key = "/mpm/sources";
    b.what = "the gas sources' step bound";
  }
  return b;
}

}  // namespace tetfsi::run
