/// @file complex_mesher.cpp
/// The one CGAL Mesh_3 translation unit: build_complex() and mesh_solid() (complex_mesher.hpp).
/// The fluid container is the box (its 12 triangles) or any closed surface; both take the same path.
///
/// Domain: CGAL::Polyhedral_complex_mesh_domain_3 with one patch per closed surface. For an
/// outward-oriented surface CGAL 5.5.1 wants the subdomain pair as (inside, outside): box or container (1, 0),
/// solid i (2 + i, 1) (the header's wording is the other way round, the code is not). Sharp edges of the box and of piecewise-flat solids (facet
/// normals differing by > kFeatureAngleDeg) are protected as features so corners are kept.
/// Sequential mesher only (the parallel one lost subdomains in the probe); all random generators
/// are seeded so the result is deterministic.
#include "mesh/complex_mesher.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_complex_mesh_domain_3.h>
#include <CGAL/Polyhedron_incremental_builder_3.h>
#include <CGAL/Random.h>
#include <CGAL/assertions.h>
#include <CGAL/exceptions.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "mesh/features.hpp"
#include "mesh/primitives.hpp"
#include "mesh/surface_checks.hpp"
#include "support/number_text.hpp"

namespace tetfsi::mesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polyhedron = CGAL::Mesh_polyhedron_3<K>::type;
using Domain = CGAL::Polyhedral_complex_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
using Triangles = std::vector<K::Triangle_3>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;

constexpr double kFeatureAngleDeg = 60.0;  ///< sharp-edge angle of the box and of flat solids [deg]
/// Sliver removal targets [deg of dihedral angle]: perturbation moves vertices of tets under
/// kPerturbBoundDeg, exudation reweights those under kExudeBoundDeg. Measured (bunny in a box,
/// 16k tets): bounds (5, 15) -> min dihedral 5.6 deg in 1.6 s; (10, 10) -> 10 deg in 33 s;
/// none -> 0.4 deg.
constexpr double kPerturbBoundDeg = 5.0;
constexpr double kExudeBoundDeg = 15.0;
constexpr unsigned kSeed = 0;              ///< seed of every CGAL random generator used here

/// Builds a CGAL polyhedron from plain arrays (the input is already checked closed and manifold).
class Builder : public CGAL::Modifier_base<Polyhedron::HalfedgeDS> {
 public:
  explicit Builder(const SurfaceMesh& s) : s_(s) {}
  void operator()(Polyhedron::HalfedgeDS& hds) override {
    CGAL::Polyhedron_incremental_builder_3<Polyhedron::HalfedgeDS> b(hds, true);
    b.begin_surface(s_.vertices.size(), s_.triangles.size());
    for (const auto& v : s_.vertices) b.add_vertex(K::Point_3(v.x(), v.y(), v.z()));
    for (const auto& t : s_.triangles) {
      b.begin_facet();
      for (int i : t) b.add_vertex_to_facet(i);
      b.end_facet();
    }
    b.end_surface();
  }

 private:
  const SurfaceMesh& s_;
};

Polyhedron to_polyhedron(const SurfaceMesh& s, const std::string& name) {
  Polyhedron p;
  Builder builder(s);
  p.delegate(builder);
  if (p.size_of_facets() != s.triangles.size() || !p.is_closed())
    throw MeshError(name + ": CGAL could not build a closed polyhedron from the surface");
  return p;
}

/// Target size [m] at a point: h(d) = h_near + (h_far - h_near) * min(1, d / grading_distance),
/// d the distance to the nearest solid surface (AABB tree query). Used for edges, facets and cells.
struct SizingField {
  using FT = K::FT;
  using Index = Domain::Index;
  const Tree* tree = nullptr;
  double h_near = 0.1, h_far = 0.1, grading = 0.0;
  const std::function<double(const Eigen::Vector3d&)>* size_at = nullptr;  ///< MeshSizing::size_at
  FT operator()(const K::Point_3& p, int /*dim*/, const Index& /*index*/) const {
    const double graded = tree == nullptr || grading <= 0.0 || h_near == h_far
                              ? h_far
                              : h_near + (h_far - h_near) * std::min(1.0, std::sqrt(tree->squared_distance(p)) / grading);
    if (size_at == nullptr || !*size_at) return graded;
    return std::min(graded, (*size_at)(Eigen::Vector3d(p.x(), p.y(), p.z())));
  }
};

void check_sizing(const MeshSizing& s) {
  if (!(s.edge_length > 0.0) || !std::isfinite(s.edge_length))
    throw MeshError("mesh sizing: edge_length must be > 0 (got " + number_text(s.edge_length) + ")");
  if (s.edge_length_near_solids < 0.0 || s.grading_distance < 0.0 || s.facet_distance < 0.0)
    throw MeshError("mesh sizing: edge_length_near_solids, grading_distance, facet_distance must be >= 0");
}

/// Initial points of the refinement. make_mesh_3 seeds the surfaces with points where rays from
/// the bounding-box centre meet *any* surface (Polyhedral_mesh_domain_3::Construct_initial_points
/// uses an any-intersection query), so all seeds can land on the box; a solid that no initial
/// Voronoi edge crosses was then never found: a 0.2 m sphere in a 1.2 m box came out as fluid
/// with 23 solid cells of ~1300. So after the feature protection make_mesh_3 would do, every
/// surface gets up to kSeedsPerSurface of its own input vertices (which lie on it exactly) as
/// surface vertices of its patch (patch ids follow the order of `surfaces`, from 1), plus CGAL's
/// own initial points.
constexpr int kSeedsPerSurface = 24;
void seed_every_surface(C3t3& c3t3, const Domain& domain, const Criteria& criteria,
                        const std::vector<SurfaceMesh>& surfaces) {
  CGAL::Mesh_3::internal::init_c3t3_with_features(c3t3, domain, criteria);
  auto weighted = c3t3.triangulation().geom_traits().construct_weighted_point_3_object();
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const auto& vs = surfaces[i].vertices;
    const std::size_t stride = std::max<std::size_t>(1, vs.size() / kSeedsPerSurface);
    const auto index = domain.index_from_surface_patch_index(static_cast<Domain::Surface_patch_index>(i + 1));
    for (std::size_t k = 0; k < vs.size(); k += stride) {
      const auto v = c3t3.triangulation().insert(weighted(K::Point_3(vs[k].x(), vs[k].y(), vs[k].z())));
      if (v == Tr::Vertex_handle()) continue;  // hidden by a feature's protecting ball
      if (c3t3.in_dimension(v) < 2) continue;  // already a protected feature vertex
      c3t3.set_dimension(v, 2);
      c3t3.set_index(v, index);
    }
  }
  CGAL::Mesh_3::internal::init_c3t3(c3t3, domain, criteria, -1);
}

/// Runs Mesh_3 on the given surfaces with subdomain pairs (inside, outside) and converts the
/// complex to a TetMesh: vertices compacted (numbered in order of first use by a complex cell),
/// tets positively oriented, labels = CGAL subdomain indices.
TetMesh mesh_3_unguarded(const std::vector<SurfaceMesh>& surfaces, const std::vector<std::string>& names,
                         const std::vector<std::pair<int, int>>& pairs, const std::vector<double>& feature_angles,
                         const Triangles& graded_to, const MeshSizing& sizing) {
  CGAL::get_default_random() = CGAL::Random(kSeed);
  CGAL::Random rng(kSeed);

  std::vector<Polyhedron> polys;
  polys.reserve(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) polys.push_back(to_polyhedron(surfaces[i], names[i]));
  Domain domain(polys.begin(), polys.end(), pairs.begin(), pairs.end(), &rng);
  // Features chosen per surface (features.hpp) rather than with domain.detect_features(angle),
  // which applies one angle to every surface and would protect the scattered creases of scans.
  std::vector<std::vector<K::Point_3>> polylines;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    if (feature_angles[i] <= 0.0) continue;
    for (const auto& line : sharp_polylines(surfaces[i], feature_angles[i])) {
      polylines.emplace_back();
      for (const auto& q : line) polylines.back().emplace_back(q.x(), q.y(), q.z());
    }
  }
  domain.add_features(polylines.begin(), polylines.end());

  Tree tree(graded_to.begin(), graded_to.end());
  if (!graded_to.empty()) tree.accelerate_distance_queries();
  SizingField field;
  field.h_far = sizing.edge_length;
  field.h_near = sizing.edge_length_near_solids > 0.0 ? sizing.edge_length_near_solids : sizing.edge_length;
  field.grading = sizing.grading_distance;
  field.tree = graded_to.empty() ? nullptr : &tree;
  field.size_at = &sizing.size_at;
  const double facet_distance = sizing.facet_distance > 0.0 ? sizing.facet_distance : field.h_near / 10.0;

  namespace p = CGAL::parameters;
  Criteria criteria(p::edge_size = field, p::facet_angle = 25.0, p::facet_size = field,
                    p::facet_distance = facet_distance, p::cell_radius_edge_ratio = 3.0,
                    p::cell_size = field);
  // Sliver removal without time limit (CGAL's default limit is the time refinement took, which
  // makes the mesh depend on the machine's load: seen 15771 vs 15774 tets for the same input), but
  // with target bounds, since an unbounded perturbation ran for minutes (sphere: 242 s).
  C3t3 c3t3;
  seed_every_surface(c3t3, domain, criteria, surfaces);
  CGAL::refine_mesh_3(c3t3, domain, criteria, p::no_lloyd(), p::no_odt(), p::no_perturb(), p::no_exude());
  CGAL::perturb_mesh_3(c3t3, domain, p::time_limit = 0.0, p::sliver_bound = kPerturbBoundDeg);
  CGAL::exude_mesh_3(c3t3, p::time_limit = 0.0, p::sliver_bound = kExudeBoundDeg);

  TetMesh out;
  std::map<Tr::Vertex_handle, int> index;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    std::array<int, 4> tet{};
    for (int k = 0; k < 4; ++k) {
      const auto v = c->vertex(k);
      auto it = index.find(v);
      if (it == index.end()) {
        it = index.emplace(v, out.num_vertices()).first;
        const auto& q = v->point().point();
        out.vertices.emplace_back(q.x(), q.y(), q.z());
      }
      tet[k] = it->second;
    }
    out.tets.push_back(tet);
    if (signed_volume(out, out.num_tets() - 1) < 0.0) std::swap(out.tets.back()[0], out.tets.back()[1]);
    out.subdomain.push_back(static_cast<int>(c3t3.subdomain_index(c)));
  }
  return out;
}

/// mesh_3_unguarded with CGAL's failures (assertions, preconditions, errors: CGAL throws them as
/// CGAL::Failure_exception) turned into a MeshError: they come from input CGAL cannot mesh in
/// double precision (coordinates far from the origin compared with the sizes, sizes near the
/// smallest double), which the scene checks refuse first (apps/run/preflight.hpp).
TetMesh run_mesh_3(const std::vector<SurfaceMesh>& surfaces, const std::vector<std::string>& names,
                   const std::vector<std::pair<int, int>>& pairs, const std::vector<double>& feature_angles,
                   const Triangles& graded_to, const MeshSizing& sizing) {
  check_sizing(sizing);
  // On some failures (a point "already inserted on surface") CGAL 5.5 Mesh_3 dumps its complex as
  // dump-bug.mesh and dump-bug.binary.cgal into the working directory before it throws, whatever
  // the build flags. tetfsi writes nothing outside its output folder: dumps that were not there
  // before are removed. (Switching the dump off by specialising CGAL::Dump_c3t3 for this complex
  // type changed the meshes themselves: seen 6419 instead of 6489 tets for bar_compare_ci.)
  static const char* const dumps[] = {"dump-bug.mesh", "dump-bug.binary.cgal", "dump-bug-c3t3.polylines.txt"};
  bool existed[3];
  for (int k = 0; k < 3; ++k) existed[k] = std::filesystem::exists(dumps[k]);
  try {
    return mesh_3_unguarded(surfaces, names, pairs, feature_angles, graded_to, sizing);
  } catch (const CGAL::Failure_exception& e) {
    std::error_code ignored;
    for (int k = 0; k < 3; ++k)
      if (!existed[k]) std::filesystem::remove(dumps[k], ignored);
    throw MeshError("CGAL Mesh_3 failed on this input (" + e.message() + (e.expression().empty() ? "" : ": " + e.expression()) +
                    "); the sizes (mesh.edge_length, facet_distance) or coordinates are out of the range the mesher "
                    "resolves in double precision");
  }
}

void append_triangles(const SurfaceMesh& s, Triangles& out) {
  for (const auto& t : s.triangles) {
    const auto& a = s.vertices[t[0]];
    const auto& b = s.vertices[t[1]];
    const auto& c = s.vertices[t[2]];
    out.emplace_back(K::Point_3(a.x(), a.y(), a.z()), K::Point_3(b.x(), b.y(), b.z()),
                     K::Point_3(c.x(), c.y(), c.z()));
  }
}

std::string solid_name(std::size_t i) { return "solid " + std::to_string(i); }

/// Feature angle of a solid surface (MeshSizing::solid_feature_angle_deg); 0 means no features.
double solid_feature_angle(const SurfaceMesh& s, const MeshSizing& sizing) {
  if (sizing.solid_feature_angle_deg >= 0.0) return sizing.solid_feature_angle_deg;
  return is_piecewise_flat(s, 1.0, kFeatureAngleDeg) ? kFeatureAngleDeg : 0.0;
}

/// The cavity surface of a solid, validated (flipped outward if needed) and checked to lie
/// strictly inside the solid's (already validated) outer surface.
SurfaceMesh checked_cavity(const SurfaceMesh& cavity, const SurfaceMesh& outer, const std::string& solid) {
  SurfaceMesh c = cavity;
  validate_surface(c, solid + " cavity");
  if (!surface_inside(c, outer))
    throw MeshError(solid + " cavity: not strictly inside the solid's outer surface (the surfaces meet or the "
                    "cavity lies outside)");
  return c;
}

}  // namespace

TetMesh build_complex(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing) {
  return build_complex(lo, hi, solids, sizing, {});
}

namespace {

/// Throws unless solid surface `s` (named `name`) lies strictly inside the container: the box
/// [lo, hi] when `box` is set (every vertex strictly inside), else the closed `container` surface.
void check_inside_container(const SurfaceMesh& s, const std::string& name, bool box, const Eigen::Vector3d& lo,
                            const Eigen::Vector3d& hi, const SurfaceMesh& container) {
  if (!box) {
    if (!surface_inside(s, container))
      throw MeshError(name + ": not strictly inside the fluid container (the surfaces meet or the solid lies outside)");
    return;
  }
  for (int v = 0; v < s.num_vertices(); ++v) {
    if (!((s.vertices[v] - lo).array() > 0.0).all() || !((hi - s.vertices[v]).array() > 0.0).all()) {
      std::ostringstream msg;
      msg << name << ": not strictly inside the box (vertex " << v << " at (" << s.vertices[v].transpose() << "))";
      throw MeshError(msg.str());
    }
  }
}

/// Largest relative change of a solid's volume from its surfaces to its tets. A coarse mesh of a
/// curved solid cuts its curvature: the test suite's 196 meshings keep 92.1% (a ball of radius
/// 0.1 m at CI size) to 100%. A solid thinner than the tets near it can collapse into a few slivers
/// instead (a 3 mm sheet next to 3 cm tets kept 0.015% of its volume, a 5 mm one 0.06%), and must
/// not run: the bound lies between the two, three times the largest loss of a sound mesh.
constexpr double kMaxSolidVolumeChange = 0.25;

/// @throws MeshError naming the solid whose tets hold a volume more than kMaxSolidVolumeChange
///         away from what its outer surface (minus its cavity) encloses
void check_solid_volumes(const TetMesh& mesh, const std::vector<SurfaceMesh>& outer,
                         const std::vector<SurfaceMesh>& cavities) {
  std::vector<double> meshed(outer.size(), 0.0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int i = mesh.subdomain[t] - solid_subdomain(0);
    if (i >= 0 && i < static_cast<int>(outer.size())) meshed[i] += std::abs(signed_volume(mesh, t));
  }
  for (std::size_t i = 0; i < outer.size(); ++i) {
    double enclosed = enclosed_volume(outer[i]);
    if (!cavities.empty() && !cavities[i].triangles.empty()) enclosed -= std::abs(enclosed_volume(cavities[i]));
    if (!(enclosed > 0) || std::abs(meshed[i] - enclosed) <= kMaxSolidVolumeChange * enclosed) continue;
    throw MeshError(solid_name(i) + ": its tets hold " + number_text(100 * meshed[i] / enclosed) + "% of the " +
                    number_text(enclosed) + " m^3 its surface encloses (more than " +
                    number_text(100 * kMaxSolidVolumeChange) + "% off): the solid is thinner than the mesh "
                    "near it resolves; make edge_length_near_solids (and facet_distance) smaller than its "
                    "thickness, or thicken it");
  }
}

/// build_complex for a container surface (the box's 12 triangles when `box` is set).
TetMesh complex_in_container(const SurfaceMesh& container, const std::string& container_name, bool box,
                             const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing,
                             const std::vector<SurfaceMesh>& cavities) {
  if (!cavities.empty() && cavities.size() != solids.size())
    throw MeshError("mesh: " + std::to_string(cavities.size()) + " cavity surfaces for " +
                    std::to_string(solids.size()) + " solids (give one per solid, empty for none)");
  std::vector<SurfaceMesh> surfaces{container};
  if (!box) validate_surface(surfaces[0], container_name);
  Eigen::Vector3d lo = surfaces[0].vertices[0], hi = lo;
  for (const auto& v : surfaces[0].vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  std::vector<std::string> names{container_name};
  std::vector<std::pair<int, int>> pairs{{kFluidSubdomain, 0}};
  std::vector<double> feature_angles{kFeatureAngleDeg};
  std::vector<SurfaceMesh> outer;  // the solids' outer surfaces, for the overlap checks
  Triangles solid_triangles;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    SurfaceMesh s = solids[i];
    const std::string name = solid_name(i);
    validate_surface(s, name);  // closed, manifold, oriented, no self-intersection; flips inward ones
    check_inside_container(s, name, box, lo, hi, surfaces[0]);
    for (std::size_t j = 0; j < i; ++j) {
      if (surfaces_intersect(outer[j], s))
        throw MeshError(name + " and " + solid_name(j) + " overlap (surfaces intersect or one contains the other)");
    }
    outer.push_back(s);
    surfaces.push_back(s);
    names.push_back(name);
    pairs.emplace_back(solid_subdomain(static_cast<int>(i)), kFluidSubdomain);
    feature_angles.push_back(solid_feature_angle(s, sizing));
    append_triangles(s, solid_triangles);
    if (!cavities.empty() && !cavities[i].triangles.empty()) {
      surfaces.push_back(checked_cavity(cavities[i], s, name));
      names.push_back(name + " cavity");
      pairs.emplace_back(kFluidSubdomain, solid_subdomain(static_cast<int>(i)));
      feature_angles.push_back(solid_feature_angle(surfaces.back(), sizing));
      append_triangles(surfaces.back(), solid_triangles);
    }
  }
  TetMesh mesh = run_mesh_3(surfaces, names, pairs, feature_angles, solid_triangles, sizing);

  std::vector<int> count(solids.size() + 2, 0);
  for (int label : mesh.subdomain) {
    if (label < kFluidSubdomain || label >= static_cast<int>(count.size()))
      throw MeshError("meshing produced an unexpected subdomain label " + std::to_string(label));
    ++count[label];
  }
  if (count[kFluidSubdomain] == 0) throw MeshError("meshing produced no fluid tets");
  for (std::size_t i = 0; i < solids.size(); ++i) {
    if (count[solid_subdomain(static_cast<int>(i))] == 0)
      throw MeshError(solid_name(i) + ": meshing produced no tets (solid smaller than the edge length?)");
  }
  check_solid_volumes(mesh, outer, cavities);
  return mesh;
}

}  // namespace

TetMesh build_complex(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing,
                      const std::vector<SurfaceMesh>& cavities) {
  if (!((hi - lo).array() > 0.0).all())
    throw MeshError("mesh box: hi must exceed lo on every axis");
  SurfaceMesh box = make_box(hi - lo);
  for (auto& v : box.vertices) v += 0.5 * (lo + hi);
  return complex_in_container(box, "fluid box", true, solids, sizing, cavities);
}

TetMesh build_complex(const SurfaceMesh& container, const std::vector<SurfaceMesh>& solids, const MeshSizing& sizing,
                      const std::vector<SurfaceMesh>& cavities) {
  if (container.vertices.empty()) throw MeshError("fluid container: the surface is empty");
  return complex_in_container(container, "fluid container", false, solids, sizing, cavities);
}

TetMesh mesh_filled_shell(const SurfaceMesh& outer, const SurfaceMesh& cavity, const MeshSizing& sizing) {
  SurfaceMesh s = outer;
  validate_surface(s, "shell");
  const SurfaceMesh c = checked_cavity(cavity, s, "shell");
  Triangles solid_triangles;
  append_triangles(s, solid_triangles);
  append_triangles(c, solid_triangles);
  const int shell = solid_subdomain(0);
  TetMesh mesh = run_mesh_3({s, c}, {"shell", "shell cavity"}, {{shell, 0}, {kFluidSubdomain, shell}},
                            {solid_feature_angle(s, sizing), solid_feature_angle(c, sizing)}, solid_triangles, sizing);
  int fluid = 0, solid = 0;
  for (int label : mesh.subdomain) {
    if (label != kFluidSubdomain && label != shell)
      throw MeshError("shell: meshing produced an unexpected subdomain label " + std::to_string(label));
    (label == shell ? solid : fluid) += 1;
  }
  if (solid == 0) throw MeshError("shell: meshing produced no solid tets (wall thinner than the edge length?)");
  if (fluid == 0) throw MeshError("shell cavity: meshing produced no fluid tets (cavity smaller than the edge length?)");
  return mesh;
}

TetMesh mesh_solid(const SurfaceMesh& surface, const MeshSizing& sizing, int subdomain) {
  SurfaceMesh s = surface;
  validate_surface(s, "solid");
  TetMesh mesh = run_mesh_3({s}, {"solid"}, {{1, 0}}, {solid_feature_angle(s, sizing)}, {}, sizing);
  if (mesh.tets.empty()) throw MeshError("solid: meshing produced no tets (solid smaller than the edge length?)");
  for (int& label : mesh.subdomain) {
    if (label != 1) throw MeshError("solid: meshing produced an unexpected subdomain label " + std::to_string(label));
    label = subdomain;
  }
  return mesh;
}

}  // namespace tetfsi::mesh
