#include "apps/run/solid_params.hpp"

#include "apps/run/scene_values.hpp"

namespace tetfsi::run {

solid::TetMaterial tet_material(const scene::Json& m) {
  solid::TetMaterial mat;
  mat.density = m.at("density").get<double>();
  mat.youngs_modulus = m.at("youngs_modulus").get<double>();
  mat.poisson_ratio = m.at("poissons_ratio").get<double>();
  mat.law = m.at("constitutive") == "neohookean" ? solid::ConstitutiveLaw::kStableNeoHookean
                                                 : solid::ConstitutiveLaw::kStVK;
  mat.rayleigh_alpha = m.at("rayleigh_alpha").get<double>();
  mat.rayleigh_beta = m.at("rayleigh_beta").get<double>();
  return mat;
}

solid::TetModelOptions tet_model_options(const scene::Json& m) {
  solid::TetModelOptions options;
  options.project_spd = m.at("constitutive") == "neohookean";
  return options;
}

solid::hex::Material hex_material(const scene::Json& m) {
  solid::hex::Material mat;
  mat.law = m.at("constitutive") == "neohookean" ? solid::hex::MaterialLaw::NeoHookean
                                                 : solid::hex::MaterialLaw::StVenantKirchhoff;
  mat.youngs_modulus = m.at("youngs_modulus").get<double>();
  mat.poisson_ratio = m.at("poissons_ratio").get<double>();
  mat.density = m.at("density").get<double>();
  return mat;
}

solid::NewmarkSettings newmark_settings(const scene::Json& solid, const scene::Json& scene, double h) {
  solid::NewmarkSettings settings;
  settings.time_step = h;
  settings.rayleigh_alpha = solid.at("material").at("rayleigh_alpha").get<double>();
  settings.rayleigh_beta = solid.at("material").at("rayleigh_beta").get<double>();
  settings.gravity = vec3(scene.at("simulation").at("gravity"));
  settings.scheme = solid::parse_newmark_scheme(solid.at("integrator").at("scheme").get<std::string>());
  settings.solver = solid::parse_solver_kind(solid.at("integrator").at("linear_solver").get<std::string>());
  return settings;
}

}  // namespace tetfsi::run
