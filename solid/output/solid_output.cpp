#include "solid/output/solid_output.hpp"

#include <cmath>

#include "solid/solid_error.hpp"

namespace tetfsi::solid {

mesh::io::UnstructuredGrid solid_grid(const TetModel& model, const Eigen::VectorXd& d, const Eigen::VectorXd& u) {
  if (!d.allFinite() || !u.allFinite()) throw SolidError("solid output: refusing to write a non-finite state");
  mesh::io::UnstructuredGrid grid;
  const auto& X = model.reference_positions();
  for (int v = 0; v < model.num_nodes(); ++v) grid.points.emplace_back(X.segment<3>(3 * v) + d.segment<3>(3 * v));
  for (const auto& t : model.tets()) grid.add_cell(mesh::io::VtkCell::Tetra, t);
  grid.add_point_data("displacement", 3, std::vector<double>(d.data(), d.data() + d.size()));
  grid.add_point_data("velocity", 3, std::vector<double>(u.data(), u.data() + u.size()));
  const Eigen::MatrixXd s = model.cauchy_stresses(d);
  std::vector<double> stress(6 * s.rows()), mises(s.rows());
  for (Eigen::Index t = 0; t < s.rows(); ++t) {
    for (int k = 0; k < 6; ++k) stress[6 * t + k] = s(t, k);
    const double a = s(t, 0) - s(t, 1), b = s(t, 1) - s(t, 2), c = s(t, 2) - s(t, 0);
    mises[t] = std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s(t, 3) * s(t, 3) + s(t, 4) * s(t, 4) + s(t, 5) * s(t, 5)));
  }
  grid.add_cell_data("cauchy_stress", 6, std::move(stress));
  grid.add_cell_data("von_mises", 1, std::move(mises));
  const Eigen::VectorXd J = model.volume_ratios(d);
  grid.add_cell_data("volume_ratio", 1, std::vector<double>(J.data(), J.data() + J.size()));
  return grid;
}

StatsCsv::StatsCsv(const std::filesystem::path& path) : out_(path) {
  if (!out_) throw SolidError("cannot open statistics file " + path.string());
  out_ << "step,time,assembly_s,solve_s,solver_iterations,kinetic_J,strain_J,gravity_J,spring_J,total_J,"
          "inverted,contacts\n";
}

void StatsCsv::write(const StepStats& s) {
  out_.precision(10);
  out_ << s.step << ',' << s.time << ',' << s.assembly_seconds << ',' << s.solve_seconds << ',' << s.solver_iterations
       << ',' << s.kinetic << ',' << s.strain << ',' << s.gravity_potential << ',' << s.spring << ',' << s.total()
       << ',' << s.inverted << ',' << s.contacts << '\n';
  out_.flush();
}

}  // namespace tetfsi::solid
