#include "apps/run/surface_refinement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "fluid/advection/point_locator.hpp"
#include "mesh/interface.hpp"
#include "mesh/remesh_region.hpp"
#include "mesh/surface_distance.hpp"

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

namespace {

/// h (`law`) at a copy of the solver's level set, interpolated on a copy of its mesh
/// (made at the first call if `lazy`, else now).
template <class SizeLaw>
std::function<double(const Eigen::Vector3d&)> field_on_copy(const SizeLaw& law, const fluid::FluidSolver& solver,
                                                            bool lazy) {
  struct Copy {
    fluid::FluidMesh mesh;
    Eigen::VectorXd phi;
    std::unique_ptr<fluid::PointLocator> locator;
    int hint = 0;
  };
  auto copy = std::make_shared<std::unique_ptr<Copy>>();
  const auto make = [copy, &solver] {
    *copy = std::make_unique<Copy>();
    (*copy)->mesh = solver.mesh();
    (*copy)->phi = solver.level_set();
    (*copy)->locator = std::make_unique<fluid::PointLocator>((*copy)->mesh);
  };
  if (!lazy) make();
  return [law, copy, make](const Eigen::Vector3d& x) {
    if (!*copy) make();
    Copy& c = **copy;
    const fluid::Location l = c.locator->locate(x, c.hint);
    c.hint = l.tet;
    double phi = 0;
    for (int k = 0; k < 4; ++k) phi += l.bary[k] * c.phi[c.mesh.tets[l.tet][k]];
    return law(std::abs(phi));
  };
}

}  // namespace

std::function<double(const Eigen::Vector3d&)> SurfaceRefinement::current_field(const fluid::FluidSolver& solver) const {
  // Copied at the first call: the field stays valid when the solver moves on to a new mesh (a
  // coupled step that halves itself updates the mesh twice).
  return field_on_copy(law_, solver, true);
}

void SurfaceRefinement::mark(const fluid::FluidSolver& solver) {
  const Eigen::VectorXd& phi = solver.level_set();
  refined_node_.assign(phi.size(), 0);
  for (Eigen::Index i = 0; i < phi.size(); ++i) refined_node_[i] = std::abs(phi[i]) < 3.0 * law_.surface_edge;
  fitted_ = field_on_copy(law_, solver, false);
}

std::vector<char> SurfaceRefinement::resized_tets(const mesh::TetMesh& mesh,
                                                  const std::function<double(const Eigen::Vector3d&)>& size_now) const {
  std::vector<char> tets = mesh::resized_tets(mesh, fitted_, size_now, kResize, kRings);
  if (std::find(tets.begin(), tets.end(), 1) == tets.end()) tets.clear();
  return tets;
}

bool SurfaceRefinement::left_zone(const Eigen::VectorXd& phi) const {
  if (static_cast<Eigen::Index>(refined_node_.size()) != phi.size()) return true;
  for (Eigen::Index i = 0; i < phi.size(); ++i)
    if (std::abs(phi[i]) < 1.5 * law_.surface_edge && !refined_node_[i]) return true;
  return false;
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

std::function<double(const Eigen::Vector3d&)> solid_graded_field(const mesh::TetMesh& mesh,
                                                                 const mesh::MeshSizing& sizing) {
  const double near = sizing.edge_length_near_solids, far = sizing.edge_length, grading = sizing.grading_distance;
  if (!(near > 0 && near < far && grading > 0)) return {};
  mesh::SurfaceMesh surface;  // the interface triangles, on their own vertices
  std::vector<int> index(mesh.num_vertices(), -1);
  for (const mesh::InterfaceFace& f : mesh::interface_faces(mesh)) {
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      int& i = index[f.vertices[k]];
      if (i < 0) {
        i = surface.num_vertices();
        surface.vertices.push_back(mesh.vertices[f.vertices[k]]);
      }
      tri[k] = i;
    }
    surface.triangles.push_back(tri);
  }
  if (surface.triangles.empty()) return {};
  auto distance = std::make_shared<mesh::SurfaceDistance>(surface);
  return [=](const Eigen::Vector3d& x) { return near + (far - near) * std::min(1.0, std::abs((*distance)(x)) / grading); };
}

}  // namespace tetfsi::run
