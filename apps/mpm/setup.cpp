#include "apps/mpm/setup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "apps/mpm/particle_fill.hpp"
#include "mesh/complex_mesher.hpp"  // MeshError
#include "mesh/surface_checks.hpp"
#include "mesh/surface_import.hpp"

namespace tetfsi::mpm_setup {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Size limits (bad input must not exhaust memory): about 100 bytes per grid node and 300 per particle.
constexpr double kMaxGridNodes = 3e7, kMaxParticles = 5e6, kMaxElements = 1e6;

Vec3 vec3(const Json& j) { return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()); }
std::string at(const std::string& ptr, const std::string& key) { return ptr + "/" + key; }
std::string fmt_vec(const Vec3& x) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", x[0], x[1], x[2]); }
int axis_index(const Json& j) { return j.get<std::string>()[0] - 'x'; }

/// Placement of a `file` shape: unit_scale, rotation_deg, translation.
mesh::Placement placement(const Json& shape) {
  mesh::Placement p;
  p.unit_scale = shape.at("unit_scale").get<double>();
  p.rotation_deg = vec3(shape.at("rotation_deg"));
  p.translation = vec3(shape.at("translation"));
  return p;
}

mpm::Grid make_grid(const Json& g, const std::string& ptr) {
  const Vec3 lo = vec3(g.at("lo")), hi = vec3(g.at("hi"));
  const double h = g.at("cell").get<double>();
  double nodes = 1;
  for (int a = 0; a < 3; ++a) nodes *= std::ceil((hi[a] - lo[a]) / h) + 1;
  if (!(nodes <= kMaxGridNodes))
    throw SetupError(at(ptr, "cell"), fmt::format("the grid would have {:.3g} nodes (at most {:.0e}): use a larger "
                                                  "cell or a smaller box", nodes, kMaxGridNodes));
  mpm::Grid grid = mpm::Grid::covering(lo, hi, h);
  static const char* names[6] = {"x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi"};
  for (int f = 0; f < 6; ++f) {
    const auto bc = g.at("faces").at(names[f]).get<std::string>();
    grid.faces[f] = bc == "slip" ? mpm::FaceBc::Slip : bc == "fixed" ? mpm::FaceBc::Fixed : mpm::FaceBc::Free;
  }
  const auto plane = g.at("plane_motion").get<std::string>();
  if (plane != "none") grid.constrained_axes[3 - (plane[0] - 'x') - (plane[1] - 'x')] = true;
  return grid;
}

mpm::Material make_material(const Json& m, const std::string& name, const std::string& ptr) {
  const auto type = m.at("type").get<std::string>();
  const double rho = m.at("density").get<double>();
  mpm::Material mat;
  if (type == "linear_elastic")
    mat = mpm::Material::linear_elastic(rho, m.at("youngs_modulus").get<double>(), m.at("poissons_ratio").get<double>());
  else if (type == "ideal_gas")
    mat = mpm::Material::ideal_gas(rho, m.at("gamma").get<double>(), m.at("viscosity").get<double>());
  else
    mat = mpm::Material::mie_gruneisen(rho, m.at("c0").get<double>(), m.at("s").get<double>(),
                                       m.at("gamma0").get<double>(), m.at("viscosity").get<double>());
  mat.name = name;
  try {
    mat.validate();
  } catch (const std::invalid_argument& e) {
    throw SetupError(ptr, e.what());
  }
  return mat;
}

/// Internal energy per reference volume E [J/m^3] of a fluid at density rho from `pressure` or
/// `internal_energy` of object o (neither: E = 0). Solids take neither.
double initial_energy(const Json& o, const mpm::Material& mat, double rho, const std::string& ptr) {
  const bool p_given = o.contains("pressure"), e_given = o.contains("internal_energy");
  if (mat.kind == mpm::Material::Kind::LinearElastic) {
    if (p_given || e_given)
      throw SetupError(at(ptr, p_given ? "pressure" : "internal_energy"),
                       "a linear_elastic body starts unstressed: pressure and internal_energy are for fluids");
    return 0;
  }
  if (p_given && e_given)
    throw SetupError(at(ptr, "internal_energy"), "give either pressure or internal_energy, not both");
  if (e_given) return o.at("internal_energy").get<double>();
  if (!p_given) return 0;
  const double p = o.at("pressure").get<double>();
  const auto [a, b] = mat.eos_coefficients(rho);  // p = a + b E (Lian, Liu & Zhang 2014, eqs. 66, 67)
  if (b == 0) {
    if (p != a)
      throw SetupError(at(ptr, "pressure"), fmt::format("at density {} the equation of state gives p = {} Pa whatever "
                                                        "the energy (tension is cut off): got {}", rho, a, p));
    return 0;
  }
  const double E = (p - a) / b;
  if (!(E >= 0))
    throw SetupError(at(ptr, "pressure"), fmt::format("needs a negative internal energy ({} J/m^3) at density {}: "
                                                      "raise the pressure or lower the density", E, rho));
  return E;
}

FillRegion body_region(const Json& shape, const std::string& ptr) {
  const auto type = shape.at("type").get<std::string>();
  if (type == "box") return {vec3(shape.at("lo")), vec3(shape.at("hi")), nullptr};
  if (type == "sphere") {
    const Vec3 c = vec3(shape.at("center"));
    const double R = shape.at("radius").get<double>();
    return {c - Vec3(R, R, R), c + Vec3(R, R, R), [c, R](const Vec3& x) { return (x - c).norm() < R; }};
  }
  if (type == "cylinder") {
    const Vec3 b = vec3(shape.at("base")), ax = vec3(shape.at("axis"));
    const double R = shape.at("radius").get<double>(), L = ax.norm();
    const Vec3 u = ax / L;
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      const double r = R * std::sqrt(std::max(0.0, 1 - u[a] * u[a]));
      lo[a] = std::min(b[a], b[a] + ax[a]) - r;
      hi[a] = std::max(b[a], b[a] + ax[a]) + r;
    }
    return {lo, hi, [b, u, L, R](const Vec3& x) {
              const double t = (x - b).dot(u);
              return t >= 0 && t < L && (x - b - t * u).norm() < R;
            }};
  }
  // A closed surface file.
  const mesh::Placement place = placement(shape);
  mesh::SurfaceMesh s;
  try {
    s = mesh::import_surface(shape.at("file").get<std::string>(), place);
    mesh::validate_surface(s, shape.at("file").get<std::string>());
  } catch (const mesh::MeshError& e) {
    throw SetupError(at(ptr, "file"), fmt::format("{} (a particle body needs a closed surface)", e.what()));
  }
  Vec3 lo, hi;
  mesh::bounding_box(s, lo, hi);
  return {lo, hi, inside_surface(s)};
}

/// A lattice of spacing dx from lo (centres lo + (i + 1/2) dx, as mpm::sample_lattice, n layers per
/// axis) must not put a layer on a grid node plane: such particles' far cell corners get no mass
/// and, in contact, they jitter across the plane (cell-crossing noise; a sphere on a membrane with
/// half its layers on planes blew up, mpm/README.md).
void check_lattice_off_planes(const mpm::Grid& g, const Vec3& lo, const Vec3& hi, double dx, const std::string& ptr) {
  for (int a = 0; a < 3; ++a) {
    const int n = std::max(1, static_cast<int>(std::lround((hi[a] - lo[a]) / dx)));
    for (int i = 0; i < n; ++i) {
      const double x = lo[a] + dx * (i + 0.5), s = (x - g.lo[a]) / g.dx, f = s - std::round(s);
      if (std::abs(f) < 1e-6)
        throw SetupError(ptr, fmt::format("the particle layer {} = {} lies on a grid node plane (cell {} from {} = {}): "
                                          "particles there jitter across the plane in contact; move the shape or "
                                          "/mpm/grid/lo by half a spacing", "xyz"[a], x, g.dx, "xyz"[a], g.lo[a]));
    }
  }
}

void add_bodies(Setup& s, const Json& bodies, const std::string& ptr) {
  const double cell = s.grid.dx;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const auto& b = bodies[i];
    const std::string bp = fmt::format("{}/{}", ptr, i);
    const auto name = b.at("name").get<std::string>();
    for (const auto& other : s.bodies)
      if (other.name == name) throw SetupError(at(bp, "name"), fmt::format("duplicate body name \"{}\"", name));
    const double dx = b.at("spacing").get<double>();
    if (dx > cell * (1 + 1e-12) || dx < cell / 6 * (1 - 1e-12))
      throw SetupError(at(bp, "spacing"), fmt::format("expected a spacing between cell / 6 and the cell {} m (one "
                                                      "to six particles per cell and direction), got {}", cell, dx));
    const auto mat = make_material(b.at("material"), name, at(bp, "material"));
    const double rho = b.contains("density") ? b.at("density").get<double>() : mat.rho0;
    const double E = initial_energy(b, mat, rho, bp);
    FillRegion r = body_region(b.at("shape"), at(bp, "shape"));
    if (!s.symmetry_planes.empty())  // the model is the part on the kept side of every plane
      r.inside = [planes = s.symmetry_planes, in = r.inside](const Vec3& x) {
        for (const auto& p : planes)
          if (x[p.axis] < p.position) return false;
        return !in || in(x);
      };
    const Vec3 ext = r.hi - r.lo;
    if (!(ext.minCoeff() > 0))
      throw SetupError(at(bp, "shape"), "the shape has no volume");
    if (!(ext.prod() / (dx * dx * dx) <= kMaxParticles))
      throw SetupError(at(bp, "spacing"), fmt::format("the body would have about {:.3g} particles (at most {:.0e}): use a "
                                                      "larger spacing", ext.prod() / (dx * dx * dx), kMaxParticles));
    check_lattice_off_planes(s.grid, r.lo, r.hi, dx, at(bp, "shape"));
    const auto material = static_cast<std::uint16_t>(s.materials.size());
    const std::size_t first = s.particles.size();
    const std::size_t n = mpm::sample_lattice(s.particles, r.lo, r.hi, dx, rho, E, vec3(b.at("velocity")), material, r.inside);
    if (n == 0)
      throw SetupError(at(bp, "shape"), fmt::format("no particle of spacing {} m lies inside the shape: use a smaller "
                                                    "spacing", dx));
    if (mat.kind == mpm::Material::Kind::Fluid)  // sigma = -p I (eq. 26 without the viscous part at rest): the
      for (std::size_t p = first; p < s.particles.size(); ++p)  // first critical step (eq. 21) needs p
        s.particles.stress[p] = -mat.pressure(rho, E) * mpm::Mat3::Identity();
    std::size_t outside = 0, example = first;
    for (std::size_t p = first; p < s.particles.size(); ++p)
      if (!s.grid.contains(s.particles.x[p]) && outside++ == 0) example = p;
    if (outside > 0)
      throw SetupError(at(bp, "shape"), fmt::format("{} of the body's {} particles lie outside the grid {} - {} "
                                                    "(/mpm/grid), e.g. at {}", outside, n, fmt_vec(s.grid.lo),
                                                    fmt_vec(s.grid.hi()), fmt_vec(s.particles.x[example])));
    s.materials.push_back(mat);
    s.bodies.push_back({name, material, n});
  }
}

QuadMesh membrane_shape(const Json& shape, double es, const std::string& ptr) {
  const auto type = shape.at("type").get<std::string>();
  auto limit = [&](double area) {
    if (!(area / (es * es) <= kMaxElements))
      throw SetupError(ptr.substr(0, ptr.rfind('/')) + "/element_size",
                       fmt::format("the membrane would have about {:.3g} elements (at most {:.0e}): use a larger "
                                   "element_size", area / (es * es), kMaxElements));
  };
  if (type == "rectangle") {
    const Vec3 u = vec3(shape.at("u")), v = vec3(shape.at("v"));
    if (!(u.cross(v).norm() > 1e-12 * u.norm() * v.norm()))
      throw SetupError(at(ptr, "v"), "u and v are parallel: the rectangle has no area");
    limit(u.norm() * v.norm());
    const int nu = std::max(1, static_cast<int>(std::lround(u.norm() / es)));
    const int nv = std::max(1, static_cast<int>(std::lround(v.norm() / es)));
    return mpm::rectangle_mesh(vec3(shape.at("origin")), u, v, nu, nv);
  }
  if (type == "disc") {
    const double R = shape.at("radius").get<double>();
    limit(4 * R * R);
    return disc_mesh(vec3(shape.at("center")), vec3(shape.at("normal")), R, es);
  }
  if (type == "cylinder") {
    const double R = shape.at("radius").get<double>();
    const Vec3 ax = vec3(shape.at("axis"));
    limit(2 * kPi * R * ax.norm());
    return cylinder_mesh(vec3(shape.at("base")), ax, R, es);
  }
  if (type == "box_tube") {
    const double a = shape.at("half_widths").at(0).get<double>(), b = shape.at("half_widths").at(1).get<double>();
    const double L = shape.at("length").get<double>();
    limit(4 * (a + b) * L);
    return box_tube_mesh(vec3(shape.at("base")), axis_index(shape.at("axis")), a, b, L, es);
  }
  if (type == "cushion") {
    const Vec3 sz = vec3(shape.at("size"));
    limit(2 * (sz[0] * sz[1] + sz[1] * sz[2] + sz[0] * sz[2]));
    return box_surface_mesh(vec3(shape.at("center")), sz, es);
  }
  if (type == "sphere") {
    const double R = shape.at("radius").get<double>();
    limit(4 * kPi * R * R);
    return sphere_mesh(vec3(shape.at("center")), R, es);
  }
  const mesh::Placement place = placement(shape);
  mesh::SurfaceMesh s;
  try {
    s = mesh::import_surface(shape.at("file").get<std::string>(), place);
  } catch (const mesh::MeshError& e) {
    throw SetupError(at(ptr, "file"), e.what());
  }
  if (!(3.0 * s.num_triangles() <= kMaxElements))
    throw SetupError(at(ptr, "file"), fmt::format("{} triangles make {} quads (at most {:.0e})", s.num_triangles(),
                                                  3 * s.num_triangles(), kMaxElements));
  return triangles_to_quads(s);
}

/// Node ids selected by a fixed region.
std::vector<int> region_nodes(const Setup& s, const Json& r, double tol) {
  const auto type = r.at("type").get<std::string>();
  const auto& x = s.membrane_mesh.nodes;
  std::vector<int> ids;
  if (type == "boundary") {
    std::vector<char> on(x.size(), 0);
    for (const auto& e : open_edges(x, s.membrane_mesh.quads, s.symmetry_planes, tol)) on[e[0]] = on[e[1]] = 1;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (on[i]) ids.push_back(static_cast<int>(i));
    return ids;
  }
  for (std::size_t i = 0; i < x.size(); ++i) {
    bool in = type == "all";
    if (type == "box") {
      const Vec3 lo = vec3(r.at("lo")), hi = vec3(r.at("hi"));
      in = ((x[i] - lo).array() >= -tol).all() && ((hi - x[i]).array() >= -tol).all();
    } else if (type == "plane") {
      in = std::abs(x[i][axis_index(r.at("axis"))] - r.at("position").get<double>()) <= tol;
    }
    if (in) ids.push_back(static_cast<int>(i));
  }
  return ids;
}

void add_membrane(Setup& s, const Json& m, const std::string& ptr) {
  s.membrane_name = m.at("name").get<std::string>();
  for (const auto& b : s.bodies)
    if (b.name == s.membrane_name)
      throw SetupError(at(ptr, "name"), fmt::format("\"{}\" is also the name of a body", s.membrane_name));
  const double tol = node_tolerance(s);
  const double es = m.at("element_size").get<double>();
  s.membrane_mesh = clip(membrane_shape(m.at("shape"), es, at(ptr, "shape")), s.symmetry_planes, tol);
  auto& mesh = s.membrane_mesh;
  if (mesh.quads.empty())
    throw SetupError("/mpm/symmetry_planes", "no element of the membrane lies on the kept side of the symmetry planes");
  if (const int bad = non_manifold_or_misoriented_edges(mesh.quads))
    throw SetupError(at(ptr, "shape"), fmt::format("{} edge(s) are shared by more than two elements or by two elements "
                                                   "of opposite orientation (the membrane must be a consistently "
                                                   "oriented manifold surface)", bad));
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    if (!s.grid.contains(mesh.nodes[i]))
      throw SetupError(at(ptr, "shape"), fmt::format("membrane node {} at {} lies outside the grid {} - {} (/mpm/grid)",
                                                     i, fmt_vec(mesh.nodes[i]), fmt_vec(s.grid.lo), fmt_vec(s.grid.hi())));
  s.membrane_closed = open_edges(mesh.nodes, mesh.quads, s.symmetry_planes, tol).empty();
  auto& mat = s.membrane_material;
  mat.rho = m.at("density").get<double>();
  mat.youngs = m.at("youngs_modulus").get<double>();
  mat.poisson = m.at("poissons_ratio").get<double>();
  mat.thickness = m.at("thickness").get<double>();
  mat.hourglass = m.at("hourglass").get<double>();
  try {
    mpm::Membrane check(mesh.nodes, mesh.quads, mat);  // degenerate elements, bad material
  } catch (const std::exception& e) {
    throw SetupError(at(ptr, "shape"), e.what());
  }
  s.membrane_fixed.assign(mesh.nodes.size(), {false, false, false});
  for (const auto& p : s.symmetry_planes)
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
      if (std::abs(mesh.nodes[i][p.axis] - p.position) <= tol) s.membrane_fixed[i][p.axis] = true;
  const auto& fixed = m.at("fixed");
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    const auto ids = region_nodes(s, fixed[k].at("region"), tol);
    if (ids.empty())
      throw SetupError(fmt::format("{}/fixed/{}/region", ptr, k),
                       fixed[k].at("region").at("type") == "boundary"
                           ? "the membrane has no free edge (it is closed but for the symmetry planes)"
                           : "selects no membrane node");
    const auto comps = fixed[k].at("components").get<std::string>();
    for (int id : ids)
      for (char c : comps) s.membrane_fixed[id][c - 'x'] = true;
  }
  s.membrane_velocity = vec3(m.at("velocity"));
  s.membrane_pressure = m.at("pressure").get<double>();
  s.membrane_damping = m.at("damping").get<double>();
}

void add_sources(Setup& s, const Json& sources, const Json& bodies, const std::string& ptr) {
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const auto& src = sources[k];
    const std::string sp = fmt::format("{}/{}", ptr, k);
    const auto name = src.at("body").get<std::string>();
    auto it = std::find_if(s.bodies.begin(), s.bodies.end(), [&](const Body& b) { return b.name == name; });
    if (it == s.bodies.end()) throw SetupError(at(sp, "body"), fmt::format("no body named \"{}\" in /mpm/bodies", name));
    const auto& mat = s.materials[it->material];
    if (mat.kind != mpm::Material::Kind::Fluid)
      throw SetupError(at(sp, "body"), fmt::format("body \"{}\" is a solid: a source adds fluid", name));
    mpm::GasSource g;
    g.material = it->material;
    g.density = src.contains("density") ? src.at("density").get<double>() : mat.rho0;
    g.energy = initial_energy(src, mat, g.density, sp);
    g.velocity = vec3(src.at("velocity"));
    g.mass_rate = src.at("mass_rate").get<double>();
    g.t_start = src.at("start_time").get<double>();
    g.t_end = src.at("end_time").get<double>();
    if (!(g.t_end > g.t_start)) throw SetupError(at(sp, "end_time"), "expected end_time > start_time");
    const double dx = bodies.at(it->material).at("spacing").get<double>();
    g.particle_mass = g.density * dx * dx * dx;
    const double count = g.mass_rate * (g.t_end - g.t_start) / g.particle_mass;
    if (!(count <= kMaxParticles))
      throw SetupError(at(sp, "mass_rate"), fmt::format("the source would add {:.3g} particles (at most {:.0e}): lower the "
                                                        "mass rate or the duration, or use a larger spacing", count,
                                                        kMaxParticles));
    const Vec3 lo = vec3(src.at("region").at("lo")), hi = vec3(src.at("region").at("hi"));
    check_lattice_off_planes(s.grid, lo, hi, dx, at(sp, "region"));
    mpm::Particles sites;
    mpm::sample_lattice(sites, lo, hi, dx, 1, 0, Vec3::Zero(), 0, nullptr);
    for (const auto& x : sites.x) {
      if (!s.grid.contains(x))
        throw SetupError(at(sp, "region"), fmt::format("the source region reaches outside the grid (site {})", fmt_vec(x)));
      g.sites.push_back(x);
    }
    const double c = mat.sound_speed(g.density, mat.pressure(g.density, g.energy));
    g.step_bound = s.options.cfl * s.grid.dx / (c + g.velocity.norm());
    s.sources.push_back(std::move(g));
  }
}

}  // namespace

double node_tolerance(const Setup& s) {
  return 1e-9 * (s.grid.hi() - s.grid.lo).norm();
}

Setup build_setup(const Json& m, const Vec3& gravity) {
  Setup s;
  s.grid = make_grid(m.at("grid"), "/mpm/grid");
  const auto& planes = m.at("symmetry_planes");
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const SymmetryPlane p{axis_index(planes[k].at("axis")), planes[k].at("position").get<double>()};
    if (std::abs(p.position - s.grid.lo[p.axis]) > node_tolerance(s))
      throw SetupError(fmt::format("/mpm/symmetry_planes/{}/position", k),
                       fmt::format("a symmetry plane is the grid's lower face on its axis: expected {} (/mpm/grid/lo), "
                                   "got {}", s.grid.lo[p.axis], p.position));
    s.grid.faces[2 * p.axis] = mpm::FaceBc::Slip;
    s.symmetry_planes.push_back(p);
  }
  s.options.gravity = gravity;
  s.options.cfl = m.at("mpm_cfl").get<double>();
  s.membrane_cfl = m.at("membrane_cfl").get<double>();
  add_bodies(s, m.at("bodies"), "/mpm/bodies");
  add_membrane(s, m.at("membrane"), "/mpm/membrane");
  add_sources(s, m.at("sources"), m.at("bodies"), "/mpm/sources");
  const auto& c = m.at("contact");
  s.contact.mode = c.at("mode") == "stick" ? mpm::ContactOptions::Mode::Stick : mpm::ContactOptions::Mode::Slip;
  s.contact.friction = c.at("friction").get<double>();
  s.contact.distance_factor = c.at("distance_factor").get<double>();
  return s;
}

std::unique_ptr<mpm::CoupledModel> make_model(const Setup& s) {
  mpm::MpmSolver solver(s.grid, s.materials, s.particles, s.options);
  mpm::Membrane mem(s.membrane_mesh.nodes, s.membrane_mesh.quads, s.membrane_material);
  for (auto& v : mem.velocities()) v = s.membrane_velocity;
  for (int i = 0; i < mem.num_nodes(); ++i)
    for (int a = 0; a < 3; ++a)
      if (s.membrane_fixed[i][a]) mem.fix(i, a);
  mem.set_pressure(s.membrane_pressure);
  mem.set_gravity(s.options.gravity);
  mem.set_damping(s.membrane_damping);
  return std::make_unique<mpm::CoupledModel>(std::move(solver), std::move(mem), s.contact, s.membrane_cfl,
                                                     s.sources);
}

}  // namespace tetfsi::mpm_setup
