#pragma once
/// @file preflight_mpm.hpp
/// Preflight's step estimate of an `mpm` scene (preflight.cpp): the explicit step at t = 0 of the
/// model the run builds (apps/mpm/setup.hpp), so that a scene whose critical step would make the
/// run take more than /simulation/max_steps is refused before it starts, naming the key that
/// limits the step.
#include <string>

#include "apps/scene/schema.hpp"

namespace tetfsi::run {

struct MpmStepBound {
  double dt = 0;       ///< largest stable step at t = 0 [s] (CoupledModel::max_dt)
  std::string key;     ///< the key that sets it: /mpm/mpm_cfl, /mpm/bodies/i/material/viscosity, /mpm/membrane_cfl
  std::string what;    ///< which bound, for the message
};

/// The step of CoupledModel::max_dt at t = 0: min(mpm_cfl x eq. 21 of Lian, Liu & Zhang 2014
/// (dx / (c + |v|) and the explicit viscous bound rho dx^2 / (8 mu)), membrane_cfl x eq. 48, the
/// sources' bounds). Particles speed up and gases compress later, so end_time / dt is a lower
/// bound on the steps. @throws mpm_setup::SetupError as the schema check does (already reported)
MpmStepBound mpm_step_bound(const scene::Json& js);

}  // namespace tetfsi::run
