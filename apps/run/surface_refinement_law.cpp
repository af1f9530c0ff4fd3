// SurfaceRefinement's size law, its scene parser and summary (surface_refinement.hpp), in a file
// of their own: the runner registry (runners.cpp) asks surface_refinement(scene).on() and must
// not link the members that work on a FluidSolver (surface_refinement.cpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "apps/run/surface_refinement.hpp"

namespace tetfsi::run {

SurfaceRefinement::SurfaceRefinement(double surface_edge, double far_edge, double grading_distance)
    : law_{surface_edge, far_edge, std::max(grading_distance, 3.0 * surface_edge)} {}

double SurfaceRefinement::SizeLaw::operator()(double d) const {
  return surface_edge + (far_edge - surface_edge) * std::clamp((d - 3.0 * surface_edge) / grading, 0.0, 1.0);
}

std::function<double(const Eigen::Vector3d&)> SurfaceRefinement::field(
    std::function<double(const Eigen::Vector3d&)> distance) const {
  return [law = law_, distance = std::move(distance)](const Eigen::Vector3d& x) { return law(std::abs(distance(x))); };
}

SurfaceRefinement surface_refinement(const scene::Json& scene) {
  const auto& f = scene.at("fluid");
  if (f.at("type") != "liquid" || f.value("fill", "domain") != "regions") return {};
  const double surface_edge = f.at("surface_edge_length").get<double>();
  if (!(surface_edge > 0)) return {};
  const auto& m = scene.at("mesh");
  return {surface_edge, m.at("edge_length").get<double>(), m.at("grading_distance").get<double>()};
}

std::string SurfaceRefinement::summary() const {
  return fmt::format("free surface: edge {:.4g} m within {:.4g} m of the surface, graded to {:.4g} m over {:.4g} m; "
                     "remeshed where h moved when the surface leaves the refined zone",
                     law_.surface_edge, 3.0 * law_.surface_edge, law_.far_edge, law_.grading);
}

}  // namespace tetfsi::run
