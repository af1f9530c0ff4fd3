#include "fluid/io/fluid_output.hpp"

namespace tetfsi::fluid {

mesh::io::UnstructuredGrid make_fluid_grid(const FluidMesh& mesh, const FluidFields& fields,
                                           const Eigen::VectorXd& pressure) {
  mesh::io::UnstructuredGrid g;
  g.points = mesh.nodes;
  for (const auto& t : mesh.tets) g.add_cell(mesh::io::VtkCell::Tetra, t);
  auto flat = [](const TetVectors& v) {
    std::vector<double> out;
    out.reserve(3 * v.size());
    for (const auto& x : v) out.insert(out.end(), {x[0], x[1], x[2]});
    return out;
  };
  auto vec = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  g.add_point_data("pressure", 1, vec(pressure));
  g.add_point_data("velocity", 3, flat(average_to_nodes(mesh, fields.velocity)));
  g.add_point_data("smoke", 1, vec(average_to_nodes(mesh, fields.smoke)));
  g.add_point_data("temperature", 1, vec(average_to_nodes(mesh, fields.temperature)));
  g.add_cell_data("velocity", 3, flat(fields.velocity));
  g.add_cell_data("smoke", 1, vec(fields.smoke));
  g.add_cell_data("temperature", 1, vec(fields.temperature));
  return g;
}

void add_liquid_fields(mesh::io::UnstructuredGrid& grid, const FluidMesh& mesh, const Eigen::VectorXd& level_set,
                       const std::vector<double>& liquid_volume) {
  grid.add_point_data("level_set", 1, std::vector<double>(level_set.data(), level_set.data() + level_set.size()));
  std::vector<double> fraction(mesh.num_tets());
  for (int t = 0; t < mesh.num_tets(); ++t) fraction[t] = liquid_volume[t] / mesh.volume[t];
  grid.add_cell_data("liquid_fraction", 1, std::move(fraction));
}

}  // namespace tetfsi::fluid
