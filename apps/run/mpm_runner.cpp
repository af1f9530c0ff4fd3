/// @file mpm_runner.cpp
/// Scenes with an `mpm` block: the MPM + Belytschko-Tsay membrane examples of Lian, Liu & Zhang
/// (2014), section 7, built by coupling/mpm/examples (make_gas_expansion, make_sphere_membrane)
/// and advanced one coupled step (section 6) per driver step.
///
/// One driver step (one stats.csv / probes.csv row) covers 1 / (frame_rate x stats_rows_per_frame)
/// of simulated time and is made of as many equal coupled steps (section 6) as the critical step
/// (section 4.4, and `simulation.dt` if given) requires: the explicit step is tiny (0.1 us in the
/// sphere cases), so a row per coupled step gave files of tens of MB. The values of a row are
/// exact at its time. A row whose energy balance has grown by more than all the energy put in
/// stops the run as diverged (ExampleModel::check_energy_growth).
///
/// stats.csv columns: wall time of the row's coupled steps by part [s] (t_particle_trial: scatter,
/// stress and nodal forces, section 6 step 2; t_membrane: step 3 and eq. 47; t_contact: step 4;
/// t_particle_update: step 5), substeps (coupled steps in the row), contact_nodes (largest count among
/// them), particles, membrane_elements; energies [J] (dimensionless
/// for gas_expansion): kinetic_mpm, internal_mpm, gravity_mpm, kinetic_membrane, strain_membrane,
/// hourglass_membrane, external_work_membrane, contact_dissipation (accumulated eq. 59 losses),
/// stored_energy (kinetic + internal + gravity of the particles, kinetic + strain + hourglass of
/// the membrane), energy_balance (stored - external work + losses: constant for an exactly
/// conservative scheme), energy_loss_fraction (1 - stored / stored at t = 0, Fig. 18); then the
/// example's probes (r_0deg, r_90deg, r_min, r_max or membrane_center_z, sphere_top_z /
/// membrane_corner_z). Frames: `particles` (VTU point cloud: velocity, pressure, density,
/// internal_energy), `membrane` (VTU quads: velocity, cell stress; surfaces/membrane_NNNNN.ply
/// with each quad split into two triangles).
#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "apps/run/errors.hpp"
#include "apps/run/simulation.hpp"
#include "coupling/mpm/examples/example_model.hpp"
#include "coupling/mpm/examples/frames.hpp"
#include "coupling/mpm/examples/gas_expansion.hpp"
#include "coupling/mpm/examples/sphere_membrane.hpp"

namespace tetfsi::run {
namespace {

namespace mc = tetfsi::mpm_contact;

mc::ContactOptions contact_options(const scene::Json& c) {
  mc::ContactOptions o;
  o.mode = c.at("mode") == "stick" ? mc::ContactOptions::Mode::Stick : mc::ContactOptions::Mode::Slip;
  o.friction = c.at("friction").get<double>();
  o.distance_factor = c.at("distance_factor").get<double>();
  return o;
}

/// The example's probe name for an mpm probe kind of the scene schema (apps/scene/blocks/misc.cpp).
std::string probe_name(const std::string& kind) {
  if (kind == "membrane_radius_0deg") return "r_0deg";
  if (kind == "membrane_radius_90deg") return "r_90deg";
  if (kind == "membrane_radius_min") return "r_min";
  if (kind == "membrane_radius_max") return "r_max";
  return kind;  // membrane_center_z, membrane_corner_z, sphere_top_z
}

class MpmRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, spdlog::logger& log) override {
    const auto& m = scene["mpm"];
    example_ = m.at("example").get<std::string>();
    const double t_end = scene["simulation"].at("end_time").get<double>();
    try {
      if (example_ == "gas_expansion") {
        mc::GasExpansionParams p;
        p.cell = m.at("cell").get<double>();
        p.particle_spacing = m.at("particle_spacing").get<double>();
        p.cfl = m.at("cfl").get<double>();
        p.gas_viscosity = m.at("gas_viscosity").get<double>();
        p.hourglass = m.at("hourglass").get<double>();
        p.t_end = t_end;
        p.contact = contact_options(m.at("contact"));
        model_ = mc::make_gas_expansion(p);
      } else {
        mc::SphereMembraneParams p;
        using Case = mc::SphereMembraneParams::Case;
        p.which = example_ == "membrane_on_sphere"   ? Case::MembraneOnSphere
                  : example_ == "sphere_on_membrane" ? Case::SphereOnMembrane
                                                     : Case::WaterSphere;
        p.cell = m.at("cell").get<double>();
        p.particle_spacing = m.at("particle_spacing").get<double>();
        p.mpm_cfl = m.at("mpm_cfl").get<double>();
        p.t_end = t_end;
        p.contact = contact_options(m.at("contact"));
        model_ = mc::make_sphere_membrane(p);
      }
    } catch (const std::invalid_argument& e) {
      throw InputError(fmt::format("/mpm: {}", e.what()));
    }
    const auto& sim = scene["simulation"];
    if (sim.contains("dt")) dt_cap_ = sim["dt"].get<double>();
    row_dt_ = 1.0 / (sim.at("frame_rate").get<double>() * m.at("stats_rows_per_frame").get<int>());
    energy0_ = model_->stored_energy();
    for (const auto& [name, value] : model_->probes()) probe_names_.push_back(name);
    log.info("mpm runner: example {}: {} particles, {} membrane elements, first step {:.4g} s, stored energy {:.6g}",
             example_, model_->mpm().particles().size(), model_->membrane().num_elements(), max_dt(), energy0_);
    log.info("mpm runner: simulation.gravity and simulation.cfl are not used (the examples set their own)");
  }

  std::vector<std::string> phases() const override {
    return {"particle_trial", "membrane", "contact", "particle_update"};
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c = {"substeps", "contact_nodes", "particles", "membrane_elements", "kinetic_mpm", "internal_mpm",
                                  "gravity_mpm", "kinetic_membrane", "strain_membrane", "hourglass_membrane",
                                  "external_work_membrane", "contact_dissipation", "stored_energy",
                                  "energy_balance", "energy_loss_fraction"};
    c.insert(c.end(), probe_names_.begin(), probe_names_.end());
    return c;
  }
  double max_dt() const override { return row_dt_; }

  StepReport step(double dt) override {
    long substeps = 0;
    int contact_nodes = 0;
    std::vector<double> phase_seconds(4, 0.0);
    mc::CoupledEnergies e;  // at the end of the row
    try {
      for (double left = dt; left > 0;) {
        const double h_max = std::min(dt_cap_, model_->max_dt());
        if (!(h_max > 0) || !std::isfinite(h_max))
          throw RunError(fmt::format("mpm example {}: the critical step became {} s", example_, h_max));
        // The rest of the row in equal steps of at most h_max. Shortening only the last steps to
        // land on the row time instead (57 steps, then two of 0.6) repeats the same step pattern
        // every row, and periodic step patterns can excite the explicit scheme (the membrane
        // blew up under some in tests/mpm/test_membrane.cpp before its variable-step form).
        const double steps_left = std::max(1.0, std::ceil(left / h_max * (1 - 1e-12)));
        const double h = steps_left == 1 ? left : left / steps_left;
        const auto rep = model_->step(h);
        contact_nodes = std::max(contact_nodes, rep.contact_nodes);
        phase_seconds[0] += rep.seconds_particle_trial;
        phase_seconds[1] += rep.seconds_membrane;
        phase_seconds[2] += rep.seconds_contact;
        phase_seconds[3] += rep.seconds_particle_update;
        left = steps_left == 1 ? 0.0 : left - h;
        ++substeps;
      }
      e = model_->coupling().energies();
      model_->check_energy_growth(e);  // divergence before any value is non-finite
    } catch (const std::runtime_error& err) {  // non-finite state, a particle leaving the grid, energy growth
      throw RunError(fmt::format("mpm example {} diverged: {}", example_, err.what()));
    }
    StepReport r;
    r.dt = dt;
    r.phase_seconds = phase_seconds;
    const double stored = mc::ExampleModel::stored_energy(e);
    r.values = {double(substeps), double(contact_nodes), double(model_->mpm().particles().size()),
                double(model_->membrane().num_elements()), e.mpm.kinetic, e.mpm.internal, e.mpm.gravity,
                e.membrane.kinetic, e.membrane.strain, e.membrane.hourglass, e.membrane.external_work, e.contact,
                stored, e.balance(), energy0_ != 0 ? 1 - stored / energy0_ : 0.0};
    for (const auto& [name, value] : model_->probes()) r.values.push_back(value);
    return r;
  }

  std::string non_finite() const override {
    const auto& P = model_->mpm().particles();
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (!P.x[p].allFinite()) return fmt::format("particle {}: position", p);
      if (!P.v[p].allFinite()) return fmt::format("particle {}: velocity", p);
      if (!P.stress[p].allFinite() || !std::isfinite(P.energy[p])) return fmt::format("particle {}: stress", p);
    }
    const auto& mem = model_->membrane();
    for (int i = 0; i < mem.num_nodes(); ++i) {
      if (!mem.positions()[i].allFinite()) return fmt::format("membrane node {}: position", i);
      if (!mem.velocities()[i].allFinite()) return fmt::format("membrane node {}: velocity", i);
    }
    return "";
  }

  void write_frame(Output& out, int frame, double time) override {
    out.write_grid("particles", frame, time, mc::particle_frame(model_->mpm()));
    const auto& mem = model_->membrane();
    out.write_grid("membrane", frame, time, mc::membrane_frame(mem));
    mesh::SurfaceMesh s;
    s.vertices = mem.positions();
    for (const auto& q : mem.quads()) {
      s.triangles.push_back({q[0], q[1], q[2]});
      s.triangles.push_back({q[0], q[2], q[3]});
    }
    out.write_surface("membrane", frame, s, mem.velocities());
  }

  std::vector<double> probe(const scene::Json& p) const override {
    const auto kind = p.at("kind").get<std::string>();
    if (kind == "total_energy") return {model_->stored_energy()};
    const auto name = probe_name(kind);
    for (const auto& [n, value] : model_->probes())
      if (n == name) return {value};
    return {};
  }

 private:
  std::string example_;
  std::unique_ptr<mc::ExampleModel> model_;
  double dt_cap_ = std::numeric_limits<double>::infinity();
  double row_dt_ = 0;  // simulated time per driver step (stats row) [s]
  double energy0_ = 0;
  std::vector<std::string> probe_names_;
};

}  // namespace

RunnerEntry mpm_runner() {
  return {"mpm", "MPM particles + Belytschko-Tsay membranes with grid contact (Lian, Liu & Zhang 2014)",
          [](const scene::Scene& s) { return s.json.contains("mpm"); },
          [] { return std::make_unique<MpmRunner>(); }};
}

}  // namespace tetfsi::run
