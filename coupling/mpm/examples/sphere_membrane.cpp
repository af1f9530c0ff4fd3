#include "coupling/mpm/examples/sphere_membrane.hpp"

#include <cmath>
#include <stdexcept>

#include "coupling/mpm/examples/example_model.hpp"
#include "solid/membrane/membrane_mesh.hpp"

namespace tetfsi::mpm_contact {

std::unique_ptr<ExampleModel> make_sphere_membrane(const SphereMembraneParams& prm) {
  using Case = SphereMembraneParams::Case;
  using mpm::Vec3;
  if (!(prm.cell > 0) || !(prm.particle_spacing > 0) || !(prm.t_end > 0))
    throw std::invalid_argument("sphere-membrane example: cell, particle spacing and end time must be positive");
  const double mm = 1e-3, half = 25 * mm;
  const bool drop_membrane = prm.which == Case::MembraneOnSphere;
  // Geometry and materials of the three cases.
  const double R = drop_membrane ? 15 * mm : 4.5 * mm;
  const Vec3 centre(0, 0, drop_membrane ? 15 * mm : (prm.which == Case::WaterSphere ? 5.0 * mm : 5.5 * mm));
  const double z_mem = drop_membrane ? 31 * mm : 0.0;
  mpm::Material sphere_mat = prm.which == Case::WaterSphere
                                 ? mpm::Material::mie_gruneisen(1000, 1647, 1.921, 0.1, 0.0)
                                 : mpm::Material::linear_elastic(drop_membrane ? 2750 : 750, 7e10, 0.3);
  membrane::MembraneMaterial mm_mat;
  mm_mat.rho = 750;
  mm_mat.youngs = drop_membrane ? 1e10 : (prm.which == Case::WaterSphere ? 6e4 : 7e10);
  mm_mat.poisson = 0.3;
  mm_mat.thickness = 0.1 * mm;

  // Grid: the membrane square plus a margin; z range around the action.
  const double margin = 2 * prm.cell;
  Vec3 lo(-half - margin, -half - margin, drop_membrane ? 0.0 : -25 * mm);
  const Vec3 hi(half + margin, half + margin, drop_membrane ? 40 * mm : centre[2] + R + 4 * prm.cell);
  // The particle lattice (points centre - R + spacing (k + 1/2)) must lie at in-cell positions,
  // never on a node plane: there a particle's far corners get no mass, and a lattice on the
  // planes (cell 2 mm, spacing 1 mm: every other layer) blew up in contact, the particles on the
  // planes jittering across them from step to step (cell-crossing noise). So the grid is moved
  // down by the part of a spacing that puts the lattice origin on a multiple of the spacing from
  // the grid origin: with a whole number of particles per cell they then sit at the usual
  // positions (i + 1/2) / n of their cells. At the paper's sizes the grid does not move, and the
  // lattice stays centred on the sphere in every case.
  // This holds at t = 0; layers that reach a plane later are handled by MpmSolver (close_stencil).
  const double dx = prm.particle_spacing, per_cell = prm.cell / dx;
  const Vec3 box_lo = centre - Vec3(R, R, R);
  const bool whole = std::abs(per_cell - std::round(per_cell)) < 1e-9 * per_cell;  // else no shift helps
  for (int a = 0; a < 3 && whole; ++a) {
    if (drop_membrane && a == 2) continue;  // the grid floor is the sphere's fixed bottom
    const double s = (box_lo[a] - lo[a]) / dx, r = s - std::floor(s);
    if (r > 1e-9 && r < 1 - 1e-9) lo[a] -= (1 - r) * dx;
  }
  mpm::Grid grid = mpm::Grid::covering(lo, hi, prm.cell);
  if (drop_membrane) grid.faces[4] = mpm::FaceBc::Fixed;  // sphere bottom fixed
  mpm::Particles P;
  const Vec3 v0 = drop_membrane ? Vec3::Zero() : Vec3(0, 0, -10.0);
  mpm::sample_lattice(P, box_lo, centre + Vec3(R, R, R), dx, sphere_mat.rho0, 0.0, v0, 0,
                      [&](const Vec3& x) { return (x - centre).norm() < R; });
  mpm::MpmOptions mopt;
  mopt.cfl = prm.mpm_cfl;
  mpm::MpmSolver solver(grid, {sphere_mat}, P, mopt);
  // Sphere top probe: the particle nearest to (0, 0, zc + R).
  std::size_t top = 0;
  for (std::size_t p = 0; p < P.size(); ++p)
    if ((P.x[p] - (centre + Vec3(0, 0, R))).norm() < (P.x[top] - (centre + Vec3(0, 0, R))).norm()) top = p;

  const int ne = std::max(2, static_cast<int>(std::lround(2 * half / prm.cell)));
  const auto mesh = membrane::rectangle_mesh(Vec3(-half, -half, z_mem), Vec3(2 * half, 0, 0), Vec3(0, 2 * half, 0), ne, ne);
  membrane::Membrane mem(mesh.nodes, mesh.quads, mm_mat);
  if (drop_membrane) {
    for (auto& v : mem.velocities()) v = Vec3(0, 0, -50.0);
  } else {
    mem.fix_where([&](const Vec3& x) { return std::abs(std::abs(x[0]) - half) < 1e-9 || std::abs(std::abs(x[1]) - half) < 1e-9; },
                  {true, true, true});
  }
  int centre_node = 0, corner_node = 0;
  for (int k = 0; k < mem.num_nodes(); ++k) {
    if (mem.positions()[k].head<2>().norm() < mem.positions()[centre_node].head<2>().norm()) centre_node = k;
    if ((mem.positions()[k].head<2>() - Eigen::Vector2d(-half, -half)).norm() < 1e-9) corner_node = k;
  }

  auto model = std::make_unique<ExampleModel>(std::move(solver), std::move(mem), prm.contact, 1.0);
  const ExampleModel* m = model.get();
  model->set_probes([m, centre_node, corner_node, top, drop_membrane] {
    const double second = drop_membrane ? m->membrane().positions()[corner_node][2] : m->mpm().particles().x[top][2];
    return ExampleModel::Probes{{"membrane_center_z", m->membrane().positions()[centre_node][2]},
                                {drop_membrane ? "membrane_corner_z" : "sphere_top_z", second}};
  });
  return model;
}

SphereMembraneResult run_sphere_membrane(const SphereMembraneParams& prm,
                                         const std::function<void(const StepRecord&)>& on_record) {
  auto model = make_sphere_membrane(prm);
  SphereMembraneResult res;
  res.particles = model->mpm().particles().size();
  res.elements = model->membrane().num_elements();
  res.min_membrane_center_z = model->probes()[0].second;
  res.energy_initial = model->stored_energy();
  auto record = [&](long step, double t, double dt, int contacts) {
    if (on_record) on_record(model->record(step, t, dt, contacts));
  };
  record(0, 0, 0, 0);
  double t = 0;
  long step = 0;
  while (t < prm.t_end * (1 - 1e-12)) {
    const double dt = std::min(model->max_dt(), prm.t_end - t);
    const auto rep = model->step(dt);
    t += dt;
    ++step;
    res.min_membrane_center_z = std::min(res.min_membrane_center_z, model->probes()[0].second);
    if (step % prm.record_every == 0 || t >= prm.t_end * (1 - 1e-12)) record(step, t, dt, rep.contact_nodes);
  }
  const auto probes = model->probes();
  res.steps = step;
  res.particle_updates = step * static_cast<long>(res.particles);
  res.membrane_center_z = probes[0].second;
  res.second_probe_z = probes[1].second;
  res.energy_final = model->stored_energy();
  res.contact_dissipated = model->coupling().energies().contact;
  return res;
}

}  // namespace tetfsi::mpm_contact
