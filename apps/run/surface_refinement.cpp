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

std::function<double(const Eigen::Vector3d&)> solid_graded_field(const mesh::TetMesh& mesh,
                                                                 const mesh::MeshSizing& sizing) {
  const double near = sizing.edge_length_near_solids, far = sizing.edge_length, grading = sizing.grading_distance;
  if (!(near > 0 && near < far && grading > 0)) return {};
  // The solids' boundary triangles (faces of one solid tet only), on their own vertices: on a
  // conforming complex these are the interface triangles, found from the solid tets alone (the
  // solids are a few percent of the tets, and this runs at every refit).
  struct SolidFace {
    std::array<int, 3> key, vertices;
    bool operator<(const SolidFace& o) const { return key < o.key; }
  };
  std::vector<SolidFace> faces;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    if (mesh.subdomain[t] == mesh::kFluidSubdomain) continue;
    for (const auto& f : mesh::kTetFaceVertices) {
      SolidFace face{{}, {mesh.tets[t][f[0]], mesh.tets[t][f[1]], mesh.tets[t][f[2]]}};
      face.key = face.vertices;
      std::sort(face.key.begin(), face.key.end());
      faces.push_back(face);
    }
  }
  std::sort(faces.begin(), faces.end());
  mesh::SurfaceMesh surface;
  std::vector<int> index(mesh.num_vertices(), -1);
  for (std::size_t a = 0; a < faces.size(); ++a) {
    if ((a > 0 && faces[a - 1].key == faces[a].key) || (a + 1 < faces.size() && faces[a + 1].key == faces[a].key))
      continue;  // between two solid tets
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      int& i = index[faces[a].vertices[k]];
      if (i < 0) {
        i = surface.num_vertices();
        surface.vertices.push_back(mesh.vertices[faces[a].vertices[k]]);
      }
      tri[k] = i;
    }
    surface.triangles.push_back(tri);
  }
  if (surface.triangles.empty()) return {};
  auto distance = std::make_shared<mesh::SurfaceDistance>(surface);
  return [=](const Eigen::Vector3d& x) { return near + (far - near) * std::min(1.0, distance->unsigned_distance(x) / grading); };
}

}  // namespace tetfsi::run
