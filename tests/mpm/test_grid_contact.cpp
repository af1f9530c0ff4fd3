// Grid contact between an MPM body and a membrane (coupling/mpm/): impenetrability at three grid
// resolutions and momentum conservation by the contact forces (Lian, Liu & Zhang 2014, section 5).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "coupling/mpm/grid_contact.hpp"
#include "solid/membrane/membrane_mesh.hpp"

using namespace tetfsi;
using mpm::Vec3;

namespace {

membrane::MembraneMaterial sheet() {
  membrane::MembraneMaterial m;
  m.rho = 1000;
  m.youngs = 1e5;
  m.poisson = 0.3;
  m.thickness = 0.002;
  return m;
}

/// Elastic block [0.2, 0.8]^2 x [0, 0.2] on a fixed floor; a 0.4 x 0.4 membrane starts 0.1 above it
/// falling at 1 m/s under gravity. Returns (lowest membrane z over the run) - (block top).
double drop_membrane_on_block(double h, int* contact_steps, double* final_vz) {
  mpm::Grid g = mpm::Grid::covering(Vec3(0, 0, 0), Vec3(1, 1, 0.6), h);
  g.faces[4] = mpm::FaceBc::Fixed;
  mpm::Particles P;
  const double top = 0.2;
  mpm::sample_lattice(P, Vec3(0.2, 0.2, 0), Vec3(0.8, 0.8, top), h / 2, 1000, 0, Vec3::Zero(), 0, nullptr);
  double surface = 0;  // top particle centres + half a spacing (0.1875 for h = 0.075)
  for (const auto& x : P.x) surface = std::max(surface, x[2] + h / 4);
  mpm::MpmOptions opt;
  opt.gravity = Vec3(0, 0, -9.81);
  mpm::MpmSolver solver(g, {mpm::Material::linear_elastic(1000, 1e6, 0.3)}, P, opt);
  auto mesh = membrane::rectangle_mesh(Vec3(0.3013, 0.3011, top + 0.1), Vec3(0.4, 0, 0), Vec3(0, 0.4, 0), 8, 8);
  membrane::Membrane mem(mesh.nodes, mesh.quads, sheet());
  mem.set_gravity(opt.gravity);
  for (auto& v : mem.velocities()) v = Vec3(0, 0, -1.0);
  mpm_contact::MpmMembraneCoupling coupling(solver, mem);
  double lowest = 1e9;
  *contact_steps = 0;
  const double dt = coupling.critical_time_step();
  for (double t = 0; t < 0.3; t += dt) {
    const auto rep = coupling.step(dt);
    if (rep.contact_nodes > 0) ++*contact_steps;
    for (const auto& x : mem.positions()) lowest = std::min(lowest, x[2]);
  }
  double vz = 0, m = 0;
  for (int k = 0; k < mem.num_nodes(); ++k) {
    vz += mem.masses()[k] * mem.velocities()[k][2];
    m += mem.masses()[k];
  }
  *final_vz = vz / m;
  return lowest - surface;
}

}  // namespace

TEST(GridContact, MembraneDoesNotPassThroughBlockAtThreeResolutions) {
  for (double h : {0.1, 0.075, 0.05}) {
    int contact_steps = 0;
    double vz = 0;
    const double gap = drop_membrane_on_block(h, &contact_steps, &vz);
    std::printf("[drop] h=%.3f lowest membrane z - block surface = %+.4f (%.2f cells), contact steps=%d, final mean vz=%.3f\n",
                h, gap, gap / h, contact_steps, vz);
    EXPECT_GT(contact_steps, 0);
    // The block's surface is the top particle centres + half a spacing. The contact
    // confirms at gaps below 0.25 h, so the membrane rests at most that far above it; passing
    // through would put it about 0.2 below.
    EXPECT_GT(gap, -0.1 * h);
    EXPECT_LT(gap, 0.5 * h);
    EXPECT_GT(vz, -0.1);  // it was stopped (free fall would give about -3.9 m/s at t = 0.3)
  }
}

TEST(GridContact, ContactForcesConserveMomentum) {
  // No gravity, no walls: a membrane thrown obliquely at a free elastic block.
  const double h = 0.1;
  mpm::Grid g = mpm::Grid::covering(Vec3(0, 0, 0), Vec3(1.2, 1.2, 1.0), h);
  mpm::Particles P;
  mpm::sample_lattice(P, Vec3(0.3013, 0.3021, 0.2017), Vec3(0.9013, 0.9021, 0.4017), h / 2, 1000, 0,
                      Vec3::Zero(), 0, nullptr);
  mpm::MpmSolver solver(g, {mpm::Material::linear_elastic(1000, 1e6, 0.3)}, P);
  auto mesh = membrane::rectangle_mesh(Vec3(0.4031, 0.4043, 0.5029), Vec3(0.4, 0, 0), Vec3(0, 0.4, 0), 6, 6);
  membrane::Membrane mem(mesh.nodes, mesh.quads, sheet());
  for (auto& v : mem.velocities()) v = Vec3(0.3, 0.1, -1.5);
  for (auto opts : {mpm_contact::ContactOptions{mpm_contact::ContactOptions::Mode::Slip, 0.3, 0.25},
                    mpm_contact::ContactOptions{mpm_contact::ContactOptions::Mode::Stick, 0.0, 0.25}}) {
    mpm::MpmSolver s = solver;
    membrane::Membrane m = mem;
    mpm_contact::MpmMembraneCoupling coupling(s, m, opts);
    const Vec3 p0 = coupling.total_momentum();
    double impulse = 0, worst_step = 0;
    const double dt = coupling.critical_time_step();
    for (double t = 0; t < 0.15; t += dt) {
      const auto rep = coupling.step(dt);
      impulse += rep.impulse_on_membrane.norm();
      worst_step = std::max(worst_step, (rep.impulse_on_membrane + rep.impulse_on_mpm).norm());
    }
    const Vec3 p1 = coupling.total_momentum();
    std::printf("[momentum] mode=%s |P0|=%.6f |P1-P0|=%.3e total contact impulse=%.4f\n",
                opts.mode == mpm_contact::ContactOptions::Mode::Slip ? "slip" : "stick", p0.norm(), (p1 - p0).norm(),
                impulse);
    EXPECT_GT(impulse, 0.1 * p0.norm());  // the contact did act
    EXPECT_LT(worst_step, 1e-14 * impulse);
    EXPECT_LT((p1 - p0).norm(), 1e-12 * p0.norm());
  }
}

#include <functional>
#include <memory>

#include <tbb/global_control.h>

#include "apps/mpm/probes.hpp"
#include "apps/mpm/setup.hpp"
#include "apps/scene/scene.hpp"
#include "coupling/mpm/frames.hpp"
#include "tests/test_support.hpp"

namespace {

/// A committed mpm scene (data/scenes/<name>.json) built as the mpm runner builds it, with `patch`
/// applied to its resolved /mpm block; probes in the scene's order.
struct SceneModel {
  mpm_setup::Setup setup;
  std::vector<mpm_setup::Probe> probes;
  std::unique_ptr<mpm_contact::CoupledModel> model;
  double probe(std::size_t i) const { return mpm_setup::evaluate(probes[i], setup, *model); }
  double stored() const { return model->stored_energy(); }
};

SceneModel scene_model(const std::string& name, const std::function<void(nlohmann::json&)>& patch = nullptr) {
  const auto sc = scene::load_scene(std::filesystem::path(TETFSI_SOURCE_DIR) / "data" / "scenes" / (name + ".json"));
  nlohmann::json m = sc["mpm"];
  if (patch) patch(m);
  SceneModel r;
  r.setup = mpm_setup::build_setup(m, Vec3::Zero());
  r.probes = mpm_setup::resolve_probes(r.setup, sc["probes"]);
  r.model = mpm_setup::make_model(r.setup);
  return r;
}

/// Advances to t_end with the model's largest stable step; calls `each` after every step.
void run_to(mpm_contact::CoupledModel& m, double t_end, const std::function<void(long, int)>& each = nullptr) {
  long step = 0;
  for (double t = 0; t < t_end * (1 - 1e-12);) {
    const double dt = std::min(m.max_dt(), t_end - t);
    const int contacts = m.step(dt).contact_nodes;
    t += dt;
    if (each) each(++step, contacts);
  }
}

}  // namespace

TEST(GasExpansion, EarlyExpansionKeepsGasInsideAndBalancesEnergy) {
  // Section 7.3 at a coarse particle spacing (0.05 instead of 0.025, data/scenes/gas_expansion_ci.json)
  // for the first 0.3 time units: the gas pushes the membrane out; no particle may leave the
  // membrane polygon and the stored energy plus the contact dissipation must stay equal to the
  // initial energy.
  auto sm = scene_model("gas_expansion_ci");
  auto& model = *sm.model;
  const double e0 = sm.stored();
  int outside = 0;
  double worst_balance = 0;
  run_to(model, 0.3, [&](long step, int) {
    if (step % 25) return;
    const auto e = model.coupling().energies();
    worst_balance = std::max(worst_balance, std::abs(mpm_contact::CoupledModel::stored_energy(e) + e.contact - e0) / e0);
    // Quarter polygon: origin, membrane line at z = 0 (the first nodes), back to the origin.
    std::vector<Eigen::Vector2d> poly{Eigen::Vector2d::Zero()};
    const auto& X = model.membrane().positions();
    for (int k = 0; k < model.membrane().num_nodes() / 2; ++k) poly.push_back(X[k].head<2>());
    for (const auto& x : model.mpm().particles().x) {
      bool in = false;  // even-odd rule
      for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
        if ((poly[i][1] > x[1]) != (poly[j][1] > x[1]) &&
            x[0] < (poly[j][0] - poly[i][0]) * (x[1] - poly[i][1]) / (poly[j][1] - poly[i][1]) + poly[i][0])
          in = !in;
      if (!in) ++outside;
    }
  });
  std::printf("[gas] t=0.3: r_0deg=%.4f r_90deg=%.4f, worst |stored + contact - E0|/E0 = %.2e, particles outside = %d\n",
              sm.probe(0), sm.probe(1), worst_balance, outside);
  EXPECT_NEAR(e0, 25.0 * 0.45 * 0.95 * 0.1, 1e-9);  // E0 V0 of the quarter gas block (Table 2)
  EXPECT_EQ(outside, 0);
  EXPECT_LT(worst_balance, 0.01);
  EXPECT_GT(sm.probe(0), 0.8);  // the short side was pushed out from 0.5
}

TEST(GasExpansion, FramesAreReadableVtu) {
  auto sm = scene_model("gas_expansion_ci");
  test::TempDir dir("mpm_frames");
  mesh::io::write_vtu(dir.path() / "particles.vtu", mpm_contact::particle_frame(sm.model->mpm()));
  mesh::io::write_vtu(dir.path() / "membrane.vtu", mpm_contact::membrane_frame(sm.model->membrane()));
  int status = 0;
  EXPECT_EQ(test::vtk_describe(dir.path() / "particles.vtu", &status),
            "342 342 p:velocity:3 p:pressure:1 p:density:1 p:internal_energy:1\n");
  EXPECT_EQ(status, 0);
  EXPECT_EQ(test::vtk_describe(dir.path() / "membrane.vtu", &status), "32 15 p:velocity:3 c:stress:9\n");
  EXPECT_EQ(status, 0);
}

TEST(GasExpansion, SettlesToPaperRadiusAndEnergyLoss) {
  // Section 7.3 acceptance at a coarse particle spacing (0.05; the paper's 0.025 runs in
  // bench_mpm): by t = 3 the membrane has settled near a circle of radius 0.96 (within 2%; the
  // radii change by less than 0.1% after t = 2.5) and 3-7% of the energy has been lost (paper:
  // about 5%, Fig. 18). The loss keeps creeping up after settling (about 0.85% per time unit at
  // this spacing and step, see coupling/mpm/README.md), which is why the end time matters.
  auto sm = scene_model("gas_expansion_ci");
  const double e0 = sm.stored();
  run_to(*sm.model, 3.0);
  const double lost = 1 - sm.stored() / e0;
  std::printf("[gas settled] r_0deg=%.4f r_90deg=%.4f energy lost=%.2f%%\n", sm.probe(0), sm.probe(1), 100 * lost);
  EXPECT_NEAR(sm.probe(0) / 0.96, 1.0, 0.02);
  EXPECT_NEAR(sm.probe(1) / 0.96, 1.0, 0.02);
  EXPECT_GT(lost, 0.03);
  EXPECT_LT(lost, 0.07);
}

namespace {

struct EnergyTrace {
  double max_gain = 0;     ///< max over steps of stored / E0 - 1
  double max_balance = 0;  ///< max over steps of |stored + contact dissipation - E0| / E0
  double final_stored = 0, final_dissipated = 0;  ///< / E0
  int contact_steps = 0;
};

/// Section 7.1b (elastic sphere at 10 m/s on a clamped membrane, data/scenes/sphere_on_membrane.json)
/// at cell 2 mm with the paper's particle spacing 0.5 mm (grid: the membrane square plus two cells,
/// up to four cells above the sphere), advanced to t_end with the given contact.
EnergyTrace sphere_on_membrane_energy(mpm_contact::ContactOptions contact, double t_end) {
  auto sm = scene_model("sphere_on_membrane", [&](nlohmann::json& m) {
    const double cell = 2e-3, edge = 25e-3 + 2 * cell;
    m["grid"]["lo"] = {-edge, -edge, -25e-3};
    m["grid"]["hi"] = {edge, edge, 5.5e-3 + 4.5e-3 + 4 * cell};
    m["grid"]["cell"] = cell;
    m["membrane"]["element_size"] = cell;
    m["contact"]["mode"] = contact.mode == mpm_contact::ContactOptions::Mode::Slip ? "slip" : "stick";
    m["contact"]["friction"] = contact.friction;
    m["contact"]["distance_factor"] = contact.distance_factor;
  });
  auto& model = *sm.model;
  const double e0 = sm.stored();
  EnergyTrace tr;
  run_to(model, t_end, [&](long, int contacts) {
    if (contacts > 0) ++tr.contact_steps;
    const double stored = model.stored_energy(), diss = model.coupling().energies().contact;
    tr.max_gain = std::max(tr.max_gain, stored / e0 - 1);
    tr.max_balance = std::max(tr.max_balance, std::abs(stored + diss - e0) / e0);
    tr.final_stored = stored / e0;
    tr.final_dissipated = diss / e0;
  });
  return tr;
}

}  // namespace

TEST(GridContact, SlipContactDoesNotGainEnergyAndTheLossIsBookedAsDissipation) {
  // The contact force of eqs. (55)-(58) brings the two bodies' normal velocities together at a
  // grid node: on the grid it can only remove kinetic energy. Computed from the grid trial
  // momentum p_I^{n+1/2}, it did positive work on the particles (FLIP maps velocity changes with
  // the consistent mass, p_I with the lumped one): this case gained 8x its energy by 0.15 ms with
  // distance_factor 1.0 (and 8% by 0.3 ms with 0.25). With the particle-side momentum it cannot.
  // Stored energy = kinetic + elastic of the sphere + kinetic + strain + hourglass of the
  // membrane (no external loads); the loss must reappear as contact dissipation, measured with
  // mid-step velocities on the particles and FE nodes.
  using Mode = mpm_contact::ContactOptions::Mode;
  struct Case {
    mpm_contact::ContactOptions contact;
    double t_end;
  };
  for (const auto& c : {Case{{Mode::Slip, 0.0, 1.0}, 0.15e-3}, Case{{Mode::Slip, 0.3, 0.25}, 0.15e-3}}) {
    const auto tr = sphere_on_membrane_energy(c.contact, c.t_end);
    std::printf("[slip energy] friction %.1f, distance_factor %.2f, t %.2f ms: %d contact steps, max gain %+.2e, final stored %.4f + "
                "dissipated %.4f, worst |balance - 1| %.2e\n",
                c.contact.friction, c.contact.distance_factor, c.t_end * 1e3, tr.contact_steps, tr.max_gain, tr.final_stored,
                tr.final_dissipated, tr.max_balance);
    EXPECT_GT(tr.contact_steps, 50);
    EXPECT_LT(tr.max_gain, 1e-3);  // never above E0 by more than 0.1%
    EXPECT_GT(tr.final_dissipated, 0.01);  // the contact did dissipate
    EXPECT_LT(tr.max_balance, 2e-3);
  }
}

TEST(GridContact, CoupledRunIsBitIdenticalForOneAndTwoThreads) {
  // Same input + thread count => same output; the per-cell passes (each cell writes only its own
  // sums, each node adds its cells in a fixed order) make it hold across thread counts too. Gas
  // expansion (7.3) at the paper's spacing 0.025 for 0.05 time units: about 800 coupled steps with
  // contact on most of them (2,736 particles, above CellBins::kParallelMin: the parallel branches
  // of the particle passes and of the contact passes).
  auto run = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    auto sm = scene_model("gas_expansion");
    auto* model = sm.model.get();
    EXPECT_GE(model->mpm().particles().size(), mpm::CellBins::kParallelMin);
    int contacts = 0;
    run_to(*model, 0.05, [&](long, int c) { contacts += c > 0; });
    EXPECT_GT(contacts, 100);
    const auto& P = model->mpm().particles();
    std::vector<double> state;
    for (std::size_t p = 0; p < P.size(); ++p) {
      state.insert(state.end(), P.x[p].data(), P.x[p].data() + 3);
      state.insert(state.end(), P.v[p].data(), P.v[p].data() + 3);
      state.insert(state.end(), P.stress[p].data(), P.stress[p].data() + 9);
      state.push_back(P.energy[p]);
    }
    for (const auto& x : model->membrane().positions()) state.insert(state.end(), x.data(), x.data() + 3);
    state.push_back(model->coupling().energies().contact);
    return state;
  };
  // A body large enough for the parallel branches (CellBins::kParallelMin particles, a node box
  // above 8192 nodes): an elastic ball of 33k particles spinning and breathing, 10 MPM steps.
  auto run_ball = [](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    mpm::Grid g = mpm::Grid::covering(Vec3(0, 0, 0), Vec3(1, 1, 1), 0.04);
    mpm::Particles P;
    const Vec3 c(0.5013, 0.4987, 0.5021);
    mpm::sample_lattice(P, c - Vec3(0.4, 0.4, 0.4), c + Vec3(0.4, 0.4, 0.4), 0.02, 1000, 0, Vec3::Zero(), 0,
                        [&](const Vec3& x) { return (x - c).norm() < 0.4; });
    for (std::size_t p = 0; p < P.size(); ++p) P.v[p] = Vec3(0, 0, 3).cross(P.x[p] - c) + 0.5 * (P.x[p] - c);
    EXPECT_GT(P.size(), mpm::CellBins::kParallelMin);
    mpm::MpmSolver s(g, {mpm::Material::linear_elastic(1000, 1e7, 0.3)}, P);
    for (int k = 0; k < 10; ++k) s.step(s.critical_time_step());
    std::vector<double> state;
    for (std::size_t p = 0; p < s.particles().size(); ++p) {
      state.insert(state.end(), s.particles().v[p].data(), s.particles().v[p].data() + 3);
      state.insert(state.end(), s.particles().stress[p].data(), s.particles().stress[p].data() + 9);
    }
    state.push_back(s.energies().total());
    return state;
  };
  const auto ball2 = run_ball(2), ball1 = run_ball(1);
  ASSERT_EQ(ball1.size(), ball2.size());
  EXPECT_EQ(std::memcmp(ball1.data(), ball2.data(), ball1.size() * sizeof(double)), 0);

  const auto a = run(2), b = run(2), c = run(1);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  int differ_2_2 = 0, differ_2_1 = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    differ_2_2 += std::memcmp(&a[i], &b[i], sizeof(double)) != 0;
    differ_2_1 += std::memcmp(&a[i], &c[i], sizeof(double)) != 0;
  }
  EXPECT_EQ(differ_2_2, 0);
  EXPECT_EQ(differ_2_1, 0);
}

TEST(GasExpansion, StepAboveTheCriticalStepIsCaughtByTheEnergyBalance) {
  // Four times the critical step: the explicit scheme grows exponentially. The energy-growth check
  // that the runner makes after every row (CoupledModel::check_energy_growth) must stop the run
  // while every value is still finite, before a non-finite state would.
  auto sm = scene_model("gas_expansion_ci");
  auto* model = sm.model.get();
  EXPECT_NO_THROW(model->check_energy_growth());
  const double dt = 4 * model->max_dt();
  std::string caught;
  int steps = 0;
  try {
    for (; steps < 2000; ++steps) {
      model->step(dt);
      model->check_energy_growth();
    }
  } catch (const std::runtime_error& e) {
    caught = e.what();
  }
  std::printf("[gas, 4 x critical step] stopped after %d steps: %s\n", steps, caught.c_str());
  EXPECT_NE(caught.find("energy balance grew"), std::string::npos) << caught;
  double vmax = 0;
  for (const auto& v : model->mpm().particles().v) vmax = std::max(vmax, v.norm());
  EXPECT_TRUE(std::isfinite(vmax));
}
