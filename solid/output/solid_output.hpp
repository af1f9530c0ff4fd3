#pragma once
/// @file solid_output.hpp
/// Output of a tet solid: a VTU grid of the deformed body with its fields, and the per-step
/// statistics as CSV rows (the rows of stats.csv, docs/scene_format.md).
#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <string>

#include "mesh/io/vtu_writer.hpp"
#include "solid/integrator/newmark.hpp"
#include "solid/tet/tet_model.hpp"

namespace tetfsi::solid {

/// Grid of the deformed body x = X + d with point fields "displacement" [m], "velocity" [m/s]
/// and cell fields "cauchy_stress" [Pa] (xx yy zz yz xz xy), "von_mises" [Pa], "volume_ratio"
/// (det F).
/// @throws SolidError if d or u is non-finite (never write a diverged state)
mesh::io::UnstructuredGrid solid_grid(const TetModel& model, const Eigen::VectorXd& d, const Eigen::VectorXd& u);

/// Writes StepStats rows as CSV: a header, then one row per call.
class StatsCsv {
 public:
  /// @throws SolidError if the file cannot be opened
  explicit StatsCsv(const std::filesystem::path& path);
  void write(const StepStats& stats);

 private:
  std::ofstream out_;
};

}  // namespace tetfsi::solid
