#include "coupling/mpm/examples/gas_expansion.hpp"

#include <cmath>
#include <stdexcept>

#include "coupling/mpm/examples/example_model.hpp"
#include "solid/membrane/membrane_mesh.hpp"

namespace tetfsi::mpm_contact {

std::unique_ptr<ExampleModel> make_gas_expansion(const GasExpansionParams& prm) {
  if (!(prm.cell > 0) || !(prm.particle_spacing > 0) || !(prm.t_end > 0))
    throw std::invalid_argument("gas expansion: cell, particle spacing and end time must be positive");
  const double depth = 0.1;
  // Grid: quarter domain with slip symmetry planes x = 0, y = 0 and plane motion in x-y. Two cell
  // layers in z so that the membrane nodes at z = depth lie inside the (half-open) grid box.
  mpm::Grid grid = mpm::Grid::covering(mpm::Vec3(0, 0, 0), mpm::Vec3(1.6, 1.6, 2 * depth), prm.cell);
  grid.dx = prm.cell;
  grid.cells[2] = std::max(2, static_cast<int>(std::lround(2 * depth / prm.cell)));
  grid.faces[0] = grid.faces[2] = grid.faces[4] = mpm::FaceBc::Slip;
  grid.constrained_axes = {false, false, true};
  mpm::Particles P;
  mpm::sample_lattice(P, mpm::Vec3(0, 0, 0), mpm::Vec3(0.45, 0.95, depth), prm.particle_spacing, 1.0, 25.0,
                      mpm::Vec3::Zero(), 0, nullptr);
  mpm::MpmSolver gas(grid, {mpm::Material::ideal_gas(1.0, 1.4, prm.gas_viscosity)}, P);

  // Membrane: the quarter of the 1 x 2 rectangle, counter-clockwise (normals outwards).
  std::vector<Eigen::Vector2d> line;
  const int ny = static_cast<int>(std::lround(1.0 / prm.cell)), nx = static_cast<int>(std::lround(0.5 / prm.cell));
  for (int j = 0; j <= ny; ++j) line.emplace_back(0.5, 1.0 * j / ny);
  for (int i = nx - 1; i >= 0; --i) line.emplace_back(0.5 * i / nx, 1.0);
  const auto mesh = membrane::extruded_polyline(line, 0.0, depth, 1);
  membrane::MembraneMaterial mm;
  mm.rho = 0.5;
  mm.youngs = 1e6;
  mm.poisson = 0.3;
  mm.thickness = 0.1;
  mm.hourglass = prm.hourglass;
  membrane::Membrane mem(mesh.nodes, mesh.quads, mm);
  mem.fix_where([](const membrane::Vec3&) { return true; }, {false, false, true});
  mem.fix_where([](const membrane::Vec3& x) { return std::abs(x[1]) < 1e-9; }, {false, true, false});
  mem.fix_where([](const membrane::Vec3& x) { return std::abs(x[0]) < 1e-9; }, {true, false, false});
  const int node_0deg = 0, node_90deg = static_cast<int>(line.size()) - 1;

  auto model = std::make_unique<ExampleModel>(std::move(gas), std::move(mem), prm.contact, prm.cfl / 0.9);
  const ExampleModel* m = model.get();
  model->set_probes([m, node_0deg, node_90deg] {
    const auto& x = m->membrane().positions();
    double rmin = 1e9, rmax = 0;
    for (const auto& p : x) {
      rmin = std::min(rmin, p.head<2>().norm());
      rmax = std::max(rmax, p.head<2>().norm());
    }
    return ExampleModel::Probes{
        {"r_0deg", x[node_0deg][0]}, {"r_90deg", x[node_90deg][1]}, {"r_min", rmin}, {"r_max", rmax}};
  });
  return model;
}

GasExpansionResult run_gas_expansion(const GasExpansionParams& prm,
                                     const std::function<void(const StepRecord&)>& on_record) {
  auto model = make_gas_expansion(prm);
  GasExpansionResult res;
  res.particles = model->mpm().particles().size();
  res.elements = model->membrane().num_elements();
  res.energy_initial = model->stored_energy();
  auto record = [&](long step, double t, double dt, int contacts) {
    if (on_record) on_record(model->record(step, t, dt, contacts));
  };
  record(0, 0, 0, 0);
  double t = 0;
  long step = 0;
  while (t < prm.t_end - 1e-12) {
    const double dt = std::min(model->max_dt(), prm.t_end - t);
    const auto rep = model->step(dt);
    t += dt;
    ++step;
    if (step % prm.record_every == 0 || t >= prm.t_end - 1e-12) record(step, t, dt, rep.contact_nodes);
  }
  res.steps = step;
  res.particle_updates = step * static_cast<long>(res.particles);
  const auto probes = model->probes();
  res.radius_0deg = probes[0].second;
  res.radius_90deg = probes[1].second;
  res.energy_final = model->stored_energy();
  res.contact_dissipated = model->coupling().energies().contact;
  return res;
}

}  // namespace tetfsi::mpm_contact
