#include "apps/run/preflight.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "apps/run/errors.hpp"
#include "apps/run/hex_geometry.hpp"
#include "apps/run/preflight_contact.hpp"
#include "apps/run/preflight_container.hpp"
#include "apps/run/preflight_emitters.hpp"
#include "apps/run/preflight_ignored.hpp"
#include "apps/run/preflight_liquid.hpp"
#include "apps/run/preflight_models.hpp"
#include "apps/run/preflight_mpm.hpp"
#include "apps/run/preflight_obstacles.hpp"
#include "apps/run/preflight_particles.hpp"
#include "apps/run/preflight_probes.hpp"
#include "apps/run/preflight_regions.hpp"
#include "apps/run/preflight_sizes.hpp"
#include "apps/run/preflight_volumes.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/solid_params.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_geometry.hpp"
#include "apps/run/tet_tools.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/surface_checks.hpp"

namespace tetfsi::run {
namespace {

using scene::Issue;
using scene::Json;

/// A placed solid surface with what the estimates need.
struct Placed {
  bool ok = false;              ///< read and checked
  mesh::SurfaceMesh surface;
  Eigen::Vector3d lo, hi;       ///< bounding box [m]
  double volume = 0, area = 0;  ///< [m^3], [m^2]
  double tets = -1;             ///< tets of a `volume_mesh` solid (read, not estimated); -1 otherwise
};

bool boxes_overlap(const Eigen::Vector3d& alo, const Eigen::Vector3d& ahi, const Eigen::Vector3d& blo,
                   const Eigen::Vector3d& bhi) {
  return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
}

double max_abs(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff());
}


class Checker {
 public:
  Checker(const scene::Scene& scene, const PreflightOptions& opt) : scene_(scene), js_(scene.json), opt_(opt) {}

  PreflightReport run() {
    check_scalars();
    if (!issues_.empty()) fail();  // the rest reads these values
    runner_ = &choose_runner(scene_);
    report_.runner = runner_->name;
    read_solids();
    read_liquid_regions();
    check_placements();
    check_liquid_regions();
    check_runner();
    for (auto& issue : checkpoint_issues(scene_, *runner_)) issues_.push_back(std::move(issue));
    check_load_boxes();
    check_probes();
    check_emitters();
    check_start();
    if (issues_.empty()) estimate();
    if (!issues_.empty()) fail();
    return report_;
  }

 private:
  [[noreturn]] void fail() { throw scene::SceneError(scene_.file.filename().string(), issues_); }

  void add(std::string pointer, std::string message) { issues_.push_back({std::move(pointer), std::move(message)}); }

  bool meshes_fluid() const { return js_.at("fluid").at("type") != "none" && !js_.contains("mpm"); }

  /// Finest edge length the mesher is asked for [m].
  double finest_edge() const {
    const auto& m = js_.at("mesh");
    const double h = m.at("edge_length").get<double>(), near = m.at("edge_length_near_solids").get<double>();
    return near > 0 ? std::min(h, near) : h;
  }

  /// |x| <= kMaxCoordinate and |x| <= kMaxCoordinateOverEdge * finest edge, for a key holding a point.
  void check_point(const std::string& pointer, const Json& v) {
    if (!v.is_array()) return;
    double m = 0;
    for (const auto& x : v) m = std::max(m, std::fabs(x.get<double>()));
    check_magnitude(pointer, m, "a coordinate");
  }

  void check_magnitude(const std::string& pointer, double m, const char* what) {
    if (m > kMaxCoordinate) {
      add(pointer, fmt::format("{} of {:.3g} m: tetfsi meshes scenes within {:.0e} m of the origin (double precision "
                               "resolves no mesh size out there); move the scene near the origin",
                               what, m, kMaxCoordinate));
    } else if (m > kMaxCoordinateOverEdge * finest_edge() && !edge_reported_) {
      edge_reported_ = true;
      const auto& mesh = js_.at("mesh");
      const bool near = mesh.at("edge_length_near_solids").get<double>() > 0 &&
                        mesh["edge_length_near_solids"].get<double>() < mesh.at("edge_length").get<double>();
      add(near ? "/mesh/edge_length_near_solids" : "/mesh/edge_length",
          fmt::format("an edge length of {:.3g} m is too fine for coordinates of {:.3g} m ({}): the mesher resolves "
                      "coordinates up to {:.0e} edge lengths from the origin; raise the edge length or move the scene "
                      "near the origin", finest_edge(), m, pointer, kMaxCoordinateOverEdge));
    }
  }

  void check_scalars() {
    if (js_.contains("domain")) {
      check_point("/domain/lo", js_["domain"]["lo"]);
      check_point("/domain/hi", js_["domain"]["hi"]);
      for (const char* patches : {"inflows", "open_patches"})
        for (std::size_t i = 0; i < js_["domain"][patches].size(); ++i)
          for (const char* k : {"lo", "hi"})
            check_point(fmt::format("/domain/{}/{}/{}", patches, i, k), js_["domain"][patches][i][k]);
      if (js_["domain"].contains("container") && js_["domain"]["container"].contains("center"))
        check_point("/domain/container/center", js_["domain"]["container"]["center"]);
      if (js_["domain"].contains("container") && js_["domain"]["container"].contains("translation"))
        check_point("/domain/container/translation", js_["domain"]["container"]["translation"]);
    }
    for (std::size_t i = 0; i < js_.at("solids").size(); ++i) {
      const auto& s = js_["solids"][i];
      check_point(fmt::format("/solids/{}/placement/translation", i), s["placement"]["translation"]);
      const auto& m = s["motion"];
      if (m.contains("center")) check_point(fmt::format("/solids/{}/motion/center", i), m["center"]);
      for (std::size_t k = 0; m.contains("keyframes") && k < m["keyframes"].size(); ++k)
        check_point(fmt::format("/solids/{}/motion/keyframes/{}/translation", i, k), m["keyframes"][k]["translation"]);
    }
    const auto& sim = js_.at("simulation");
    const double end = sim.at("end_time").get<double>();
    if (!std::isfinite(end)) add("/simulation/end_time", "expected a finite time");
  }

  void read_solids() {
    const auto& solids = js_.at("solids");
    placed_.resize(solids.size());
    for (std::size_t i = 0; i < solids.size(); ++i) {
      const auto& s = solids[i];
      const bool volume_mesh = s.at("geometry").at("type") == "volume_mesh";
      const std::string ptr = fmt::format(volume_mesh ? "/solids/{}/geometry/file" : "/solids/{}/geometry", i);
      // A deforming hex8 solid is meshed by the hex runner (hex_geometry.hpp); a kinematic one is a
      // surface like any other.
      const bool hex8 = s.at("model").at("type") == "hex8" && s.at("motion").at("type") == "none";
      if (hex8 && s.at("geometry").at("type") != "box" && s["geometry"]["type"] != "volume_mesh") continue;  // schema
      try {
        std::vector<std::string> warnings;
        mesh::SurfaceMesh cavity;
        Placed& p = placed_[i];
        int tets = -1;
        if (hex8 && s["geometry"]["type"] == "box") {  // counted first: a block over the limit is not built
          const auto& m = s["model"];
          const double cells = double(m["nx"].get<int>()) * m["ny"].get<int>() * m["nz"].get<int>();
          if (!(cells <= (opt_.max_tets ? *opt_.max_tets : default_max_tets()))) {
            hex_cells_ += cells;  // estimate() refuses it with the count
            continue;
          }
        }
        if (hex8) {  // the placed hex mesh the hex runner builds, its boundary, its regions
          const mesh::HexMesh hm = hex_mesh_of(s, warnings);
          hex_cells_ += hm.num_hexes();
          p.surface = hex_boundary_surface(hm);
          for (auto& [key, message] : empty_hex_regions(s, hm, fmt::format("/solids/{}", i))) add(key, message);
        } else {
          p.surface = surface_of(s, warnings, &cavity, &tets);
        }
        p.tets = tets;
        for (auto& w : warnings) report_.warnings.push_back(std::move(w));
        mesh::bounding_box(p.surface, p.lo, p.hi);
        p.volume = mesh::enclosed_volume(p.surface) - (cavity.triangles.empty() ? 0.0 : mesh::enclosed_volume(cavity));
        p.area = surface_area(p.surface) + (cavity.triangles.empty() ? 0.0 : surface_area(cavity));
        p.ok = true;
        check_magnitude(ptr, max_abs(p.lo, p.hi), "a placed vertex");
      } catch (const InputError& e) {
        add(ptr, e.what());
      } catch (const mesh::MeshError& e) {
        add(ptr, e.what());
      } catch (const std::exception& e) {  // e.g. a CGAL failure in the surface checks
        add(ptr, std::string("the surface could not be checked: ") + e.what());
      }
    }
  }

  /// Reads and checks the surface files of `mesh` liquid regions (the run would fail on them later).
  void read_liquid_regions() {
    if (!js_.contains("fluid") || !js_["fluid"].contains("regions")) return;
    const auto& regions = js_["fluid"]["regions"];
    for (std::size_t i = 0; i < regions.size(); ++i) {
      if (regions[i].at("type") != "mesh") continue;
      const std::string ptr = fmt::format("/fluid/regions/{}/file", i);
      try {
        std::vector<std::string> warnings;
        const auto surface = liquid_region_surface(regions[i], warnings);
        liquid_mesh_areas_.push_back(surface_area(surface));
        for (auto& w : warnings) report_.warnings.push_back(std::move(w));
        Eigen::Vector3d lo, hi;
        mesh::bounding_box(surface, lo, hi);
        check_magnitude(ptr, max_abs(lo, hi), "a placed vertex");
      } catch (const std::exception& e) {
        add(ptr, e.what());
      }
    }
  }

  std::string solid_name(std::size_t i) const { return js_["solids"][i]["name"].get<std::string>(); }

  /// The solids read so far, as the container, liquid and obstacle checks take them.
  std::vector<ContainedSolid> contained_solids() const {
    std::vector<ContainedSolid> solids;
    for (std::size_t i = 0; i < placed_.size(); ++i)
      solids.push_back({placed_[i].ok ? &placed_[i].surface : nullptr, solid_name(i)});
    return solids;
  }

  /// The container's checks (preflight_container.hpp) against the solids read so far.
  void check_container() {
    if (!meshes_fluid() || !js_.contains("domain")) return;
    for (auto& issue : container_issues(js_, contained_solids())) issues_.push_back(std::move(issue));
  }

  /// Every liquid region holds liquid (preflight_liquid.hpp), once the surfaces read so far are fine.
  void check_liquid_regions() {
    if (!issues_.empty() || !meshes_fluid()) return;
    for (auto& issue : liquid_region_issues(js_, contained_solids())) issues_.push_back(std::move(issue));
  }

  void check_placements() {
    const bool fluid = meshes_fluid() && js_.contains("domain");
    check_container();
    if (fluid) {
      const Eigen::Vector3d lo = vec3(js_["domain"]["lo"]), hi = vec3(js_["domain"]["hi"]);
      for (std::size_t i = 0; i < placed_.size(); ++i) {
        const auto& p = placed_[i];
        if (!p.ok) continue;
        if (!((p.lo - lo).array() > 0).all() || !((hi - p.hi).array() > 0).all())
          add(fmt::format("/solids/{}/placement", i),
              fmt::format("solid '{}' (bounding box [{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m) is not strictly "
                          "inside the domain /domain [{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}] m",
                          solid_name(i), p.lo.x(), p.lo.y(), p.lo.z(), p.hi.x(), p.hi.y(), p.hi.z(), lo.x(), lo.y(),
                          lo.z(), hi.x(), hi.y(), hi.z()));
      }
      check_contact_gap(lo, hi);
    }
    for (std::size_t i = 0; i < placed_.size(); ++i)
      for (std::size_t j = 0; j < i; ++j) {
        const auto &a = placed_[j], &b = placed_[i];
        if (!a.ok || !b.ok || !boxes_overlap(a.lo, a.hi, b.lo, b.hi)) continue;
        if (!mesh::surfaces_intersect(a.surface, b.surface)) continue;
        const std::string msg = fmt::format("solids '{}' and '{}' overlap (their surfaces intersect or one contains "
                                            "the other)", solid_name(j), solid_name(i));
        if (fluid) add(fmt::format("/solids/{}/placement", i), msg + ": the fluid mesh needs disjoint solids");
        else report_.warnings.push_back(fmt::format("/solids/{}/placement: {}; solids without a fluid do not collide "
                                                    "with each other, so they pass through", i, msg));
      }
  }

  /// Solids starting inside an obstacle (preflight_obstacles.hpp), and the values the run would
  /// ignore or cut (preflight_ignored.hpp).
  void check_start() {
    double largest = 0;  // of the tet-meshed solids (estimate_tets)
    for (std::size_t i = 0; i < placed_.size(); ++i) {
      const auto& p = placed_[i];
      if (p.ok && p.tets < 0 && js_["solids"][i]["model"]["type"] != "hex8" && runner_->name != "kinematic")
        largest = std::max(largest, (p.hi - p.lo).maxCoeff());
    }
    for (auto& issue : obstacle_issues(js_, runner_->name, contained_solids())) issues_.push_back(std::move(issue));
    for (auto& w : ignored_value_warnings(scene_, runner_->name, meshes_fluid(), largest))
      report_.warnings.push_back(std::move(w));
  }

  /// Scenes no runner simulates as written: refused rather than run in part.
  void check_runner() {
    for (auto& issue : model_mix_issues(js_, runner_->name, meshes_fluid())) issues_.push_back(std::move(issue));
    for (auto& issue : process_issues(js_, runner_->name, opt_.processes)) issues_.push_back(std::move(issue));
  }

  /// Boundary-condition and fixed-region boxes that select no node (preflight_regions.hpp).
  void check_load_boxes() {
    std::vector<PlacedBox> boxes;
    for (const auto& p : placed_) boxes.push_back({p.ok, p.lo, p.hi});
    for (auto& issue : empty_region_issues(js_, boxes, contained_solids())) issues_.push_back(std::move(issue));
  }

  void check_probes() {
    for (auto& issue : probe_issues(js_, runner_->name, runner_->probe_kinds)) issues_.push_back(std::move(issue));
  }

  /// /coupling/contact_gap against the contacts and the placed solids (preflight_contact.hpp).
  void check_contact_gap(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    std::vector<PlacedBox> boxes;
    for (const auto& p : placed_) boxes.push_back({p.ok, p.lo, p.hi});
    for (auto& issue : contact_gap_issues(js_, runner_->name, boxes, lo, hi)) issues_.push_back(std::move(issue));
  }

  void check_emitters() {
    const auto magnitude = [&](const std::string& pointer, double m) { check_magnitude(pointer, m, "a coordinate"); };
    for (auto& w : emitter_warnings(js_, meshes_fluid(), magnitude)) report_.warnings.push_back(std::move(w));
  }

  /// Tet count of a CGAL Mesh_3 mesh: a regular tet of edge h has volume h^3 / (6 sqrt 2), so a
  /// region of volume V meshed at size h holds about 6 sqrt(2) V / h^3 tets (the data/scenes meshes
  /// hold 0.3 to 0.7 of this estimate). A solid is meshed at the smaller of its size and its
  /// thickness 3V/A (1.5 t for a slab of thickness t, a/2 for a cube, r for a sphere: a slab
  /// thinner than the edge length needs edges about as short as it is thick),
  /// plus a layer of A / h^2 surface facets; with grading, a band of width grading_distance around
  /// each solid is meshed at the mean of the near and far sizes.
  double estimate_tets() {
    constexpr double kTetsPerCube = 8.485;  // 6 sqrt 2
    const auto& m = js_.at("mesh");
    const double far = m.at("edge_length").get<double>();
    const double near = finest_edge();
    const double grading = m.at("grading_distance").get<double>();
    const bool fluid = meshes_fluid();
    double n = 0, largest = -1;
    auto count = [&](double tets, std::string key, std::string what) {
      n += tets;
      if (tets > largest) largest = tets, worst_key_ = std::move(key), worst_what_ = std::move(what);
    };
    if (fluid && js_.contains("domain")) {
      const Eigen::Vector3d size = vec3(js_["domain"]["hi"]) - vec3(js_["domain"]["lo"]);
      count(kTetsPerCube * size.prod() / std::pow(far, 3), "/mesh/edge_length",
            fmt::format("the fluid box at /mesh/edge_length {:g} m", far));
      const double hs = js_["fluid"].value("surface_edge_length", 0.0);
      if (js_["fluid"]["type"] == "liquid" && hs > 0) {  // the refined band (surface_refinement.hpp)
        const double area = free_surface_area(js_, liquid_mesh_areas_);
        count(surface_band_tets(area, hs, far, grading), "/fluid/surface_edge_length",
              fmt::format("the band refined to /fluid/surface_edge_length {:g} m around the liquid's free surface "
                          "of about {:.3g} m^2", hs, area));
      }
    }
    const double facet_distance = m.at("facet_distance").get<double>();
    for (std::size_t i = 0; i < placed_.size(); ++i) {
      const auto& p = placed_[i];
      if (!p.ok || js_["solids"][i]["model"]["type"] == "hex8" || runner_->name == "kinematic") continue;  // not tet-meshed
      if (p.tets >= 0) {  // a volume mesh: its own tets
        count(p.tets, fmt::format("/solids/{}/geometry/file", i), fmt::format("the volume mesh of solid '{}'", solid_name(i)));
        continue;
      }
      const double h_solid = fluid ? near : far;  // the solid runner meshes each solid at edge_length
      const double thickness = p.area > 0 ? 3 * p.volume / p.area : h_solid;
      const std::string name = solid_name(i);
      if (thickness < h_solid)
        count(estimate_solid_tets(p.volume, p.area, h_solid), fmt::format("/solids/{}/geometry", i),
              fmt::format("solid '{}', about {:.3g} m thick (3 volume / area), thinner than the edge length "
                          "{:g} m, so meshed at its thickness", name, thickness, h_solid));
      else
        count(estimate_solid_tets(p.volume, p.area, h_solid),
              fluid && near < far ? "/mesh/edge_length_near_solids" : "/mesh/edge_length",
              fmt::format("solid '{}' at edge length {:g} m", name, h_solid));
      const double h_facet = facet_edge(h_solid, facet_distance, thickness);
      if (h_facet < h_solid)  // surface facets finer than the edge length, on both sides in a fluid
        count(kTetsPerCube * (fluid ? 2 : 1) * p.area / (h_facet * h_facet), "/mesh/facet_distance",
              fmt::format("the surface facets of solid '{}' at /mesh/facet_distance {:g} m (edges of about {:.3g} m "
                          "on its curvature radius {:.3g} m, 3 volume / area)", name, facet_distance, h_facet, thickness));
      if (fluid && grading > 0 && near < far)
        count(kTetsPerCube * p.area * grading / std::pow(0.5 * (near + far), 3), "/mesh/grading_distance",
              fmt::format("the graded band of {:g} m around solid '{}'", grading, name));
    }
    if (hex_cells_ > 0) count(hex_cells_, "/solids", "the hex8 cells (nx ny nz, or a hex mesh file's)");
    return n;
  }

  void estimate() {
    const auto& sim = js_.at("simulation");
    const auto& exp = js_.at("export");
    report_.tets = estimate_tets();
    report_.max_tets = opt_.max_tets ? *opt_.max_tets : default_max_tets();
    if (!(report_.tets <= report_.max_tets)) {
      add(worst_key_,
          fmt::format("the mesh would have about {:.3g} tets (about {} of memory; most from {}), more than the "
                      "limit of {:.3g} tets ({}): change {} or raise the limit with --max-tets",
                      report_.tets, format_bytes(report_.tets * kBytesPerTet), worst_what_, report_.max_tets,
                      opt_.max_tets ? "--max-tets" : "half of this machine's memory", worst_key_));
    }
    check_voxels();
    check_surface_voxels();
    if (issues_.empty()) report_.particles = particle_count(js_, report_.tets, issues_);
    const double end = sim.at("end_time").get<double>();
    const double frame_rate = sim.at("frame_rate").get<double>();
    report_.frames = std::floor(end * frame_rate * (1 + 1e-12)) + 1;
    const double max_steps = sim.at("max_steps").get<double>();
    report_.steps = std::max(report_.frames - 1, sim.contains("dt") ? std::ceil(end / sim["dt"].get<double>()) : 0.0);
    double load_steps = 0;  // a static analysis: a frame per load step (more after step cuts), no time steps
    for (const auto& s : js_.at("solids"))
      if (s.at("motion").at("type") == "none" && is_static(s))
        load_steps = std::max(load_steps, s.at("static").at("load_steps").get<double>());
    if (load_steps > 0) {
      report_.steps = load_steps;
      report_.frames = load_steps + 1;
    } else if (runner_->name == "mpm") {
      check_mpm_steps(end, max_steps);
    } else if (!(report_.steps <= max_steps))
      add(sim.contains("dt") && end / sim["dt"].get<double>() >= report_.frames - 1 ? "/simulation/dt" : "/simulation/frame_rate",
          fmt::format("the run would take at least {:.3g} steps (end_time {:g} s, {}), more than /simulation/max_steps "
                      "= {:g}: shorten /simulation/end_time, {}, or raise /simulation/max_steps",
                      report_.steps, end,
                      sim.contains("dt") ? fmt::format("dt {:g} s, frame_rate {:g} 1/s", sim["dt"].get<double>(), frame_rate)
                                         : fmt::format("frame_rate {:g} 1/s (one step per frame at least)", frame_rate),
                      max_steps, sim.contains("dt") ? "raise /simulation/dt or lower /simulation/frame_rate"
                                                    : "lower /simulation/frame_rate"));
    if (!issues_.empty()) return;  // the output estimate follows from the two above
    const double written = std::floor((report_.frames - 1) / exp.at("every_n_frames").get<double>()) + 1;
    double frame_bytes = 0;
    if (exp.at("vtu").get<bool>()) frame_bytes += kVtuBytesPerTet * report_.tets;
    frame_bytes += kVdbBytesPerVoxel * voxels_;
    if (exp.at("surfaces") != "none")
      for (const auto& p : placed_) frame_bytes += p.ok ? 40.0 * 2 * p.area / std::pow(finest_edge(), 2) : 0.0;
    report_.output_bytes = written * frame_bytes + 400.0 * report_.steps;
    const double max_bytes = exp.at("max_output_gb").get<double>() * 1e9;
    if (!(report_.output_bytes <= max_bytes))
      add("/simulation/frame_rate",
          fmt::format("the output would take about {} ({:.3g} frames of about {} each), more than /export/max_output_gb "
                      "= {:g}: lower /simulation/frame_rate, raise /export/every_n_frames, or raise "
                      "/export/max_output_gb",
                      format_bytes(report_.output_bytes), written, format_bytes(frame_bytes), max_bytes / 1e9));
  }

  /// An mpm scene: at least end_time / (its explicit step at t = 0) steps (preflight_mpm.hpp).
  void check_mpm_steps(double end, double max_steps) {
    MpmStepBound b;
    try {
      b = mpm_step_bound(js_);
    } catch (const std::exception&) {  // the schema check reports the setup's problems
      return;
    }
    report_.steps = std::max(report_.steps, std::ceil(end / b.dt));
    if (!(report_.steps <= max_steps))
      add(b.key, fmt::format("the run would take at least {:.3g} steps (end_time {:g} s over a step of {:.3g} s at t = 0, "
                             "{}), more than /simulation/max_steps = {:g}: change {}, shorten /simulation/end_time "
                             "or raise /simulation/max_steps",
                             report_.steps, end, b.dt, b.what, max_steps, b.key));
  }

  /// export.volumes "vdb": the voxel estimate and its limit (preflight_volumes.hpp).
  void check_voxels() {
    const auto& exp = js_.at("export");
    if (exp.at("volumes") != "vdb") return;
    if (!meshes_fluid()) {
      report_.warnings.push_back("/export/volumes: the scene has no tet-mesh fluid: no volume files are written");
      return;
    }
    voxels_ = volume_voxels(js_, 0.5 * finest_edge(), issues_);
  }

  /// export.liquid_surface "smooth" with its scale given: the voxels over the domain box
  /// (preflight_volumes.hpp; without the keys the run checks the scale it fixes at the first frame).
  void check_surface_voxels() {
    const auto& f = js_.at("fluid");
    if (!meshes_fluid() || f.at("type") != "liquid" || f.value("fill", "domain") != "regions") return;
    liquid_surface_voxels(js_, issues_);
  }

  const scene::Scene& scene_;
  const Json& js_;
  PreflightOptions opt_;
  const RunnerEntry* runner_ = nullptr;
  std::vector<Placed> placed_;
  double hex_cells_ = 0;
  std::vector<double> liquid_mesh_areas_;  ///< surface area of each `mesh` liquid region [m^2]
  double voxels_ = 0;  ///< estimated voxels of a volume frame (export.volumes)
  bool edge_reported_ = false;
  std::string worst_key_ = "/mesh/edge_length", worst_what_;
  std::vector<Issue> issues_;
  PreflightReport report_;
};

}  // namespace

double estimate_solid_tets(double volume, double area, double h) {
  constexpr double kTetsPerCube = 8.485;  // 6 sqrt 2
  const double hs = area > 0 ? std::min(h, 3 * volume / area) : h;
  return kTetsPerCube * (volume / std::pow(hs, 3) + area / (hs * hs));
}

PreflightReport preflight(const scene::Scene& scene, const PreflightOptions& options) {
  return Checker(scene, options).run();
}

}  // namespace tetfsi::run
