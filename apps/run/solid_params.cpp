#include "apps/run/solid_params.hpp"

#include <map>
#include <string>

#include "apps/run/scene_values.hpp"
#include "solid/solid_error.hpp"

namespace tetfsi::run {

solid::HyperelasticLaw hyperelastic_law(const scene::Json& m) {
  const auto law = solid::parse_hyperelastic_law(m.at("constitutive").get<std::string>());
  if (!law) throw solid::SolidError("material: unknown constitutive law " + m.at("constitutive").dump());
  return *law;
}

solid::TetMaterial tet_material(const scene::Json& m) {
  solid::TetMaterial mat;
  mat.density = m.at("density").get<double>();
  mat.youngs_modulus = m.at("youngs_modulus").get<double>();
  mat.poisson_ratio = m.at("poissons_ratio").get<double>();
  mat.law = hyperelastic_law(m);
  mat.rayleigh_alpha = m.at("rayleigh_alpha").get<double>();
  mat.rayleigh_beta = m.at("rayleigh_beta").get<double>();
  return mat;
}

solid::TetModelOptions tet_model_options(const scene::Json& m) {
  solid::TetModelOptions options;
  options.project_spd = hyperelastic_law(m) != solid::HyperelasticLaw::kStVK;
  return options;
}

solid::hex::Material hex_material(const scene::Json& m) {
  solid::hex::Material mat;
  mat.law = hyperelastic_law(m);
  mat.youngs_modulus = m.at("youngs_modulus").get<double>();
  mat.poisson_ratio = m.at("poissons_ratio").get<double>();
  mat.density = m.at("density").get<double>();
  return mat;
}

solid::NewmarkSettings newmark_settings(const scene::Json& solid, const scene::Json& scene) {
  solid::NewmarkSettings settings;
  settings.rayleigh_alpha = solid.at("material").at("rayleigh_alpha").get<double>();
  settings.rayleigh_beta = solid.at("material").at("rayleigh_beta").get<double>();
  settings.gravity = vec3(scene.at("simulation").at("gravity"));
  settings.scheme = solid::parse_newmark_scheme(solid.at("integrator").at("scheme").get<std::string>());
  settings.solver = solid::parse_solver_kind(solid.at("integrator").at("linear_solver").get<std::string>());
  return settings;
}

std::vector<solid::RegionCondition> region_conditions(const scene::Json& s, bool with_fixed_regions) {
  std::vector<solid::RegionCondition> out;
  if (with_fixed_regions)
    for (const auto& box : s.at("fixed_regions")) {
      solid::RegionCondition rc;
      rc.lo = vec3(box.at("lo"));
      rc.hi = vec3(box.at("hi"));
      rc.components.clear();
      for (const auto& c : box.at("components")) rc.components += c.get<std::string>();
      out.push_back(rc);
    }
  using K = solid::RegionCondition::Kind;
  const std::map<std::string, K> kinds = {{"fixed", K::Fixed},
                                          {"displacement", K::Displacement},
                                          {"nodal_force", K::NodalForce},
                                          {"traction", K::Traction},
                                          {"moment_rotation", K::MomentRotation},
                                          {"moment_traction", K::MomentTraction},
                                          {"body_force", K::BodyForce},
                                          {"pressure", K::Pressure}};
  for (const auto& bc : s.at("boundary_conditions")) {
    solid::RegionCondition rc;
    rc.kind = kinds.at(bc.at("type").get<std::string>());
    rc.lo = vec3(bc.at("box").at("lo"));
    rc.hi = vec3(bc.at("box").at("hi"));
    rc.components = bc.at("components").get<std::string>();
    rc.value = vec3(bc.at("value"));
    rc.axis = vec3(bc.at("axis"));
    rc.center = vec3(bc.at("center"));
    rc.angle = bc.at("angle").get<double>();
    rc.moment = bc.at("moment").get<double>();
    rc.pressure = bc.at("pressure").get<double>();
    out.push_back(rc);
  }
  return out;
}

solid::StaticOptions static_options(const scene::Json& s) {
  const auto& st = s.at("static");
  solid::StaticOptions o;
  o.load_steps = st.at("load_steps").get<int>();
  o.max_iterations = st.at("max_iterations").get<int>();
  o.residual_tolerance = st.at("residual_tolerance").get<double>();
  o.increment_tolerance = st.at("increment_tolerance").get<double>();
  o.max_step_cuts = st.at("max_step_cuts").get<int>();
  o.linear_solver = st.at("linear_solver") == "cg" ? solid::LinearSolverKind::ConjugateGradient
                                                  : solid::LinearSolverKind::Cholmod;
  return o;
}

bool is_static(const scene::Json& s) { return s.at("model").value("analysis", "dynamic") == "static"; }

}  // namespace tetfsi::run
