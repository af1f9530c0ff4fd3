#pragma once
/// @file solid_params.hpp
/// The one reader from a resolved scene's /solids/i block to the solid models' parameter structs
/// (keys and defaults: apps/scene/blocks/solids.cpp). Every runner that builds a solid reads it here.
#include "apps/scene/scene.hpp"
#include "solid/analysis/static_solver.hpp"
#include "solid/hex/material.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/loads/region_conditions.hpp"
#include "solid/tet/material.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::run {

/// /solids/i/material/constitutive: the law of every element (solid/laws/hyperelastic_law.hpp).
/// @throws solid::SolidError on a name the schema would have refused
solid::HyperelasticLaw hyperelastic_law(const scene::Json& material);

/// /solids/i/material of a tet FEM solid: E, nu, density, Rayleigh damping, constitutive law.
solid::TetMaterial tet_material(const scene::Json& material);

/// Element options /solids/i/material implies: every neo-Hookean law projects the element tangent to
/// PSD (TetModelOptions::project_spd), which keeps A positive definite under strong compression in the
/// dynamic step; the static solver uses the exact tangent wherever it is positive definite.
solid::TetModelOptions tet_model_options(const scene::Json& material);

/// /solids/i/material of a hex8 solid.
solid::hex::Material hex_material(const scene::Json& material);

/// Time integration of a solid alone: gravity (/simulation/gravity), the Rayleigh damping of
/// /solids/i/material and the scheme and linear solver of /solids/i/integrator (the runner passes
/// each step's length to NewmarkIntegrator::step(h)).
/// @throws solid::SolidError on an unknown scheme or solver name
solid::NewmarkSettings newmark_settings(const scene::Json& solid, const scene::Json& scene);

/// /solids/i/boundary_conditions as region conditions (solid/loads/region_conditions.hpp); with
/// `with_fixed_regions`, the /solids/i/fixed_regions first, as `fixed` conditions on their components.
std::vector<solid::RegionCondition> region_conditions(const scene::Json& solid, bool with_fixed_regions);

/// /solids/i/static: load stepping and Newton tolerances of `analysis: static`.
solid::StaticOptions static_options(const scene::Json& solid);

/// True if /solids/i/model/analysis is "static".
bool is_static(const scene::Json& solid);

}  // namespace tetfsi::run
