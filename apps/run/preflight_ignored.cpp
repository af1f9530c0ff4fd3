#include "apps/run/preflight_ignored.hpp"

#include <fmt/format.h>

#include "apps/run/solid_params.hpp"

namespace tetfsi::run {

std::vector<std::string> ignored_value_warnings(const scene::Scene& scene, const std::string& runner,
                                                bool meshes_fluid, double largest_meshed_solid) {
  std::vector<std::string> out;
  const auto& in = scene.input;
  auto given = [&](const char* block, const char* key) {
    return in.is_object() && in.contains(block) && in[block].is_object() && in[block].contains(key);
  };
  const auto& sim = scene["simulation"];
  if (given("simulation", "cfl")) {
    if (runner != "fluid" && runner != "coupled")
      out.push_back(fmt::format("/simulation/cfl: ignored: the {} runner (which runs this scene) has no CFL step; it "
                                "steps at /simulation/dt, else 1 / frame_rate", runner));
    else if (sim.contains("dt"))
      out.push_back("/simulation/cfl: ignored: /simulation/dt is given, and the run steps at dt");
  }
  bool load_steps = false;  // a static analysis takes load steps, not time steps
  for (const auto& s : scene["solids"]) load_steps = load_steps || (s.at("motion").at("type") == "none" && is_static(s));
  const double frame_dt = 1.0 / sim.at("frame_rate").get<double>();
  if (!load_steps && sim.contains("dt") && sim["dt"].get<double>() > frame_dt * (1 + 1e-9))
    out.push_back(fmt::format("/simulation/dt: {:g} s is longer than the frame interval 1 / frame_rate = {:g} s: every "
                              "step is cut to land on the next frame, so the run steps at {:g} s; lower "
                              "/simulation/frame_rate to step at dt", sim["dt"].get<double>(), frame_dt, frame_dt));
  const auto& fluid = scene["fluid"];
  const std::string fill = fluid.value("fill", "regions");
  if (fill != "regions" && given("fluid", "regions") && !fluid.at("regions").empty())
    out.push_back(fmt::format("/fluid/regions: ignored: /fluid/fill is \"{}\", so the liquid fills {}; set fill to "
                              "\"regions\" for a liquid with a free surface", fill,
                              fill == "domain" ? "the domain" : "the cavities"));
  const auto& obstacles = scene.json.value("obstacles", scene::Json::object());
  if (runner == "fluid" && (!obstacles.value("planes", scene::Json::array()).empty() ||
                            !obstacles.value("boxes", scene::Json::array()).empty()))
    out.push_back("/obstacles: ignored: they are for solid contact, and the fluid runner (which runs this scene) "
                  "moves no solid (use a solid with a zero motion as a fixed obstacle in the fluid)");
  const double edge = scene["mesh"].at("edge_length").get<double>();
  if (given("mesh", "edge_length") && !meshes_fluid && edge > largest_meshed_solid)
    out.push_back(largest_meshed_solid > 0
                      ? fmt::format("/mesh/edge_length: {:g} m is longer than every solid meshed at it (the largest is "
                                    "{:.3g} m across): the solids are meshed at their surfaces' resolution "
                                    "(mesh.facet_distance), not at this length", edge, largest_meshed_solid)
                      : std::string("/mesh/edge_length: ignored: no fluid and no solid of this scene is tet-meshed at "
                                    "it"));
  return out;
}

}  // namespace tetfsi::run
