/// @file mesh_only_runner.cpp
/// The runner for scenes whose physics is not implemented yet: it meshes the scene (the fluid
/// box with every solid inside as one CGAL complex, or each solid alone when there is no
/// domain), reports the mesh quality, and exports frame 0. No time stepping.
#include <fmt/format.h>

#include "apps/run/container.hpp"
#include "apps/run/scene_values.hpp"
#include "apps/run/errors.hpp"
#include "apps/run/simulation.hpp"
#include "apps/run/solid_geometry.hpp"
#include "support/stopwatch.hpp"
#include "apps/run/tet_tools.hpp"
#include "mesh/complex_mesher.hpp"
#include "mesh/interface.hpp"
#include "mesh/quality.hpp"

namespace tetfsi::run {
namespace {


class MeshOnlyRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy&, spdlog::logger& log) override {
    log.warn("no physics model runs this scene yet: meshing and exporting frame 0 only");
    const auto& js = scene.json;
    const auto& m = js.at("mesh");
    const mesh::MeshSizing sizing = mesh_sizing(m);

    Stopwatch clock;
    std::vector<mesh::SurfaceMesh> surfaces;
    for (const auto& s : js.at("solids")) {
      names_.push_back(s.at("name").get<std::string>());
      velocity_.push_back(vec3(s.at("initial_velocity")));
      std::vector<std::string> warnings;
      surfaces.push_back(surface_of(s, warnings));
      for (const auto& w : warnings) log.warn("{}", w);
    }
    try {
      if (js.contains("domain")) {
        complex_ = mesh_container(js["domain"], surfaces, sizing);
      } else {
        for (std::size_t i = 0; i < surfaces.size(); ++i) {
          auto part = mesh::mesh_solid(surfaces[i], sizing, mesh::solid_subdomain(static_cast<int>(i)));
          const int base = complex_.num_vertices();
          complex_.vertices.insert(complex_.vertices.end(), part.vertices.begin(), part.vertices.end());
          for (auto t : part.tets) {
            for (auto& v : t) v += base;
            complex_.tets.push_back(t);
            complex_.subdomain.push_back(mesh::solid_subdomain(static_cast<int>(i)));
          }
        }
      }
    } catch (const mesh::MeshError& e) {
      throw meshing_failure(e, names_);
    }
    if (complex_.subdomain.empty()) complex_.subdomain.assign(complex_.tets.size(), mesh::kFluidSubdomain);
    report_.phase_seconds = {clock.seconds()};

    has_fluid_ = js.contains("domain");
    if (has_fluid_) fluid_ = extract_subdomain(complex_, mesh::kFluidSubdomain);
    for (std::size_t i = 0; i < names_.size(); ++i)
      solids_.push_back(extract_subdomain(complex_, mesh::solid_subdomain(static_cast<int>(i))));

    const mesh::QualityReport all = mesh::quality_report(complex_);
    log.info("mesh quality: {}", all.summary());
    for (std::size_t i = 0; i < solids_.size(); ++i) {
      if (solids_[i].num_tets() == 0) throw RunError(fmt::format("meshing lost solid '{}' (no tets)", names_[i]));
      log.info("mesh: solid '{}': {} vertices, {} tets", names_[i], solids_[i].num_vertices(), solids_[i].num_tets());
    }
    if (has_fluid_) {
      const mesh::InterfaceCheck ic = mesh::check_interface(complex_);
      log.info("mesh: {} interface triangles, each shared by one fluid and one solid tet: {}",
               ic.interface_faces, ic.conforming() ? "yes" : "NO (" + ic.first_defect + ")");
      if (!ic.conforming()) log.warn("the fluid-solid interface does not conform: {}", ic.first_defect);
    }
    if (all.inverted > 0 || all.degenerate > 0)
      throw RunError(fmt::format("the mesh has {} inverted and {} flat tets", all.inverted, all.degenerate));
    report_.values = {double(complex_.num_vertices()), double(all.num_tets), double(fluid_.num_tets()),
                      double(all.num_tets - fluid_.num_tets()), all.min_dihedral_deg, all.max_dihedral_deg,
                      all.max_radius_edge};
  }

  bool time_dependent() const override { return false; }
  std::vector<std::string> phases() const override { return {"mesh"}; }
  std::vector<std::string> columns() const override {
    return {"vertices", "tets", "fluid_tets", "solid_tets", "min_dihedral_deg", "max_dihedral_deg",
            "max_radius_edge"};
  }
  double max_dt(const scene::TimeStepPolicy&) const override { return 0; }
  StepReport step(double) override { return report_; }
  StepReport setup_report() const override { return report_; }

  std::string non_finite() const override {
    for (std::size_t v = 0; v < complex_.vertices.size(); ++v)
      if (!complex_.vertices[v].allFinite()) return fmt::format("mesh vertex {} position", v);
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    if (has_fluid_) out.write_grid("fluid", frame, time, mesh::io::make_grid(fluid_));
    for (std::size_t i = 0; i < solids_.size(); ++i) {
      auto grid = mesh::io::make_grid(solids_[i]);
      std::vector<double> v;
      for (int k = 0; k < solids_[i].num_vertices(); ++k)
        v.insert(v.end(), {velocity_[i].x(), velocity_[i].y(), velocity_[i].z()});
      grid.add_point_data("velocity", 3, v);
      out.write_grid(names_[i], frame, time, grid);
      const auto surface = boundary_surface(solids_[i]);
      out.write_surface(names_[i], frame, surface,
                        std::vector<Eigen::Vector3d>(surface.vertices.size(), velocity_[i]));
    }
  }

  std::vector<double> probe(const scene::Json& p) const override {
    if (p.at("kind") == "solid_volume") {
      for (std::size_t i = 0; i < names_.size(); ++i)
        if (names_[i] == p.at("solid").get<std::string>()) {
          double v = 0;
          for (int t = 0; t < solids_[i].num_tets(); ++t) v += mesh::signed_volume(solids_[i], t);
          return {v};
        }
    }
    return {};
  }

 private:
  mesh::TetMesh complex_, fluid_;
  std::vector<mesh::TetMesh> solids_;
  std::vector<std::string> names_;
  std::vector<Eigen::Vector3d> velocity_;
  bool has_fluid_ = false;
  StepReport report_;
};

}  // namespace

std::unique_ptr<Simulation> make_mesh_only_runner() { return std::make_unique<MeshOnlyRunner>(); }

}  // namespace tetfsi::run
