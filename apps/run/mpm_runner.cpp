/// @file mpm_runner.cpp
/// Scenes with an `mpm` block: MPM particle bodies in grid contact with a Belytschko-Tsay membrane
/// (Lian, Liu & Zhang 2014), the problem built from the scene by apps/mpm (build_setup, make_model)
/// and advanced one coupled step (section 6) at a time.
///
/// One driver step (one stats.csv / probes.csv row) covers 1 / (frame_rate x stats_rows_per_frame)
/// of simulated time and is made of as many equal coupled steps (section 6) as the critical step
/// (section 4.4, and `simulation.dt` if given) requires: the explicit step is tiny (0.1 us in the
/// sphere scenes), so a row per coupled step gave files of tens of MB. The values of a row are
/// exact at its time. A row whose energy balance has grown by more than all the energy put in
/// stops the run as diverged (CoupledModel::check_energy_growth).
///
/// stats.csv columns: wall time of the row's coupled steps by part [s] (t_particle_trial: scatter,
/// stress and nodal forces, section 6 step 2; t_membrane: step 3 and eq. 47; t_contact: step 4;
/// t_particle_update: step 5), substeps (coupled steps in the row), contact_nodes (largest count among
/// them), particles, membrane_elements; energies [J] (in the scene's units): kinetic_mpm,
/// internal_mpm, gravity_mpm, kinetic_membrane, strain_membrane, hourglass_membrane,
/// external_work_membrane, contact_dissipation (accumulated eq. 59 losses), injected_energy (by the
/// sources), stored_energy (kinetic + internal + gravity of the particles, kinetic + strain +
/// hourglass of the membrane), energy_balance (stored - external work + losses - injected:
/// constant for an exactly conservative scheme), energy_loss_fraction (1 - stored / stored at
/// t = 0, Fig. 18). Probes go to probes.csv. Frames: `particles` (VTU point cloud: velocity,
/// pressure, density, internal_energy), `membrane` (VTU quads: velocity, cell stress;
/// surfaces/membrane_NNNNN.ply with each quad split into two triangles).
#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "apps/run/errors.hpp"
#include "apps/run/simulation.hpp"
#include "apps/mpm/probes.hpp"
#include "apps/mpm/setup.hpp"
#include "apps/run/scene_values.hpp"
#include "mpm/contact/frames.hpp"

namespace tetfsi::run {
namespace {

namespace mc = tetfsi::mpm;

class MpmRunner : public Simulation {
 public:
  void setup(const scene::Scene& scene, const scene::TimeStepPolicy& time_steps, spdlog::logger& log) override {
    const auto& m = scene["mpm"];
    try {
      setup_ = mpm_setup::build_setup(m, vec3(scene["simulation"].at("gravity")));
      probes_ = mpm_setup::resolve_probes(setup_, scene["probes"]);
      scene_probes_ = scene["probes"];
      model_ = mpm_setup::make_model(setup_);
      setup_.particles = {};  // the solver has its own copy (probes are resolved)
    } catch (const mpm_setup::SetupError& e) {  // validation catches these first (apps/scene/scene_schema.cpp)
      throw InputError(fmt::format("{}: {}", e.pointer(), e.what()));
    } catch (const std::exception& e) {
      throw InputError(fmt::format("/mpm: {}", e.what()));
    }
    if (time_steps.dt) dt_cap_ = *time_steps.dt;
    rows_per_frame_ = m.at("stats_rows_per_frame").get<int>();
    energy0_ = model_->stored_energy();
    for (const auto& b : setup_.bodies)
      log.info("mpm runner: body {}: {} particles ({})", b.name, b.particles, setup_.materials[b.material].name);
    log.info("mpm runner: membrane {}: {} elements, {} nodes{}; grid {} x {} x {} cells of {} m; first step {:.4g} s, "
             "stored energy {:.6g}", setup_.membrane_name, model_->membrane().num_elements(), model_->membrane().num_nodes(),
             setup_.membrane_closed ? ", closed" : "", setup_.grid.cells[0], setup_.grid.cells[1], setup_.grid.cells[2],
             setup_.grid.dx, model_->max_dt(), energy0_);
    log.info("mpm runner: simulation.cfl is not used (mpm.mpm_cfl, mpm.membrane_cfl)");
  }

  std::vector<std::string> phases() const override {
    return {"particle_trial", "membrane", "contact", "particle_update"};
  }
  std::vector<std::string> columns() const override {
    std::vector<std::string> c = {"substeps", "contact_nodes", "particles", "membrane_elements", "kinetic_mpm", "internal_mpm",
                                  "gravity_mpm", "kinetic_membrane", "strain_membrane", "hourglass_membrane",
                                  "external_work_membrane", "contact_dissipation", "injected_energy",
                                  "stored_energy", "energy_balance", "energy_loss_fraction"};
    return c;
  }
  /// One stats.csv row: 1 / (frame_rate x mpm.stats_rows_per_frame).
  double max_dt(const scene::TimeStepPolicy& time_steps) const override {
    return 1.0 / (time_steps.frame_rate * rows_per_frame_);
  }

  StepReport step(double dt) override {
    long substeps = 0;
    int contact_nodes = 0;
    std::vector<double> phase_seconds(4, 0.0);
    mc::CoupledEnergies e;  // at the end of the row
    try {
      for (double left = dt; left > 0;) {
        const double h_max = std::min(dt_cap_, model_->max_dt());
        if (!(h_max > 0) || !std::isfinite(h_max))
          throw RunError(fmt::format("mpm: the critical step became {} s", h_max));
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
      throw RunError(fmt::format("mpm run diverged: {}", err.what()));
    }
    StepReport r;
    r.dt = dt;
    r.phase_seconds = phase_seconds;
    const double stored = mc::CoupledModel::stored_energy(e);
    r.values = {double(substeps), double(contact_nodes), double(model_->mpm().particles().size()),
                double(model_->membrane().num_elements()), e.mpm.kinetic, e.mpm.internal, e.mpm.gravity,
                e.membrane.kinetic, e.membrane.strain, e.membrane.hourglass, e.membrane.external_work, e.contact,
                model_->injected_energy(), stored, model_->balance(e), energy0_ != 0 ? 1 - stored / energy0_ : 0.0};
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

  /// The coupled MPM-membrane model's state (CoupledModel::write_state).
  void write_checkpoint(BinaryWriter& out) const override { model_->write_state(out); }
  void read_checkpoint(BinaryReader& in) override { model_->read_state(in); }

  std::vector<double> probe(const scene::Json& p) const override {
    // The driver passes an element of /probes (apps/run/driver.cpp): find which.
    for (std::size_t i = 0; i < scene_probes_.size(); ++i)
      if (scene_probes_[i] == p) return {mpm_setup::evaluate(probes_[i], setup_, *model_)};
    return {};
  }

 private:
  mpm_setup::Setup setup_;
  std::vector<mpm_setup::Probe> probes_;
  std::unique_ptr<mc::CoupledModel> model_;
  /// The longest MPM-membrane substep [s]: the policy's dt if the scene gives one (the critical
  /// step decides below it).
  double dt_cap_ = std::numeric_limits<double>::infinity();
  int rows_per_frame_ = 1;  ///< mpm.stats_rows_per_frame: driver steps (stats rows) per frame
  double energy0_ = 0;
  scene::Json scene_probes_;  // /probes
};

}  // namespace

std::unique_ptr<Simulation> make_mpm_runner() { return std::make_unique<MpmRunner>(); }

}  // namespace tetfsi::run
