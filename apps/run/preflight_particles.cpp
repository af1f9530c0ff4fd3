#include "apps/run/preflight_particles.hpp"

#include <fmt/format.h>

#include "apps/run/preflight.hpp"

namespace tetfsi::run {

double particle_count(const scene::Json& js, double fluid_tets, std::vector<scene::Issue>& issues) {
  const auto& f = js.at("fluid");
  if (f.at("type") == "none" || js.contains("mpm")) return 0;
  const auto advection = f.at("advection").get<std::string>();
  if (advection != "apic" && advection != "flip") return 0;
  const double per_tet = f.at("particles_per_tet").get<double>();
  const double particles = per_tet * fluid_tets;
  if (!(particles <= default_max_particles()))
    issues.push_back({"/fluid/particles_per_tet",
                      fmt::format("the fluid would carry about {:.3g} particles ({:g} per tet over about {:.3g} tets; "
                                  "about {} of memory), more than the limit of {:.3g} particles (a quarter of this "
                                  "machine's memory at {:g} bytes per particle): lower /fluid/particles_per_tet or "
                                  "raise /mesh/edge_length",
                                  particles, per_tet, fluid_tets, format_bytes(particles * kBytesPerParticle),
                                  default_max_particles(), kBytesPerParticle)});
  return particles;
}

}  // namespace tetfsi::run
