#include "coupling/mpm/frames.hpp"

namespace tetfsi::mpm_contact {

mesh::io::UnstructuredGrid particle_frame(const mpm::MpmSolver& mpm) {
  const auto& P = mpm.particles();
  auto g = mesh::io::make_point_cloud(P.x);
  std::vector<double> vel, pres, rho, energy;
  for (std::size_t p = 0; p < P.size(); ++p) {
    vel.insert(vel.end(), {P.v[p][0], P.v[p][1], P.v[p][2]});
    pres.push_back(-P.stress[p].trace() / 3.0);
    rho.push_back(P.rho[p]);
    energy.push_back(P.energy[p]);
  }
  g.add_point_data("velocity", 3, std::move(vel));
  g.add_point_data("pressure", 1, std::move(pres));
  g.add_point_data("density", 1, std::move(rho));
  g.add_point_data("internal_energy", 1, std::move(energy));
  return g;
}

mesh::io::UnstructuredGrid membrane_frame(const membrane::Membrane& membrane) {
  mesh::io::UnstructuredGrid g;
  g.points = membrane.positions();
  for (const auto& q : membrane.quads()) g.add_cell(mesh::io::VtkCell::Quad, q);
  std::vector<double> vel, stress;
  for (const auto& v : membrane.velocities()) vel.insert(vel.end(), {v[0], v[1], v[2]});
  for (int e = 0; e < membrane.num_elements(); ++e) {
    const auto s = membrane.global_stress(e);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) stress.push_back(s(i, j));
  }
  g.add_point_data("velocity", 3, std::move(vel));
  g.add_cell_data("stress", 9, std::move(stress));
  return g;
}

}  // namespace tetfsi::mpm_contact
