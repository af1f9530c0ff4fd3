// `mpirun -n 2 tetfsi run` (parallel/: the pressure and coupled solves on PETSc with BoomerAMG,
// the rows spread over the processes) gives the probes of the one-process shared-memory run (hypre
// BoomerAMG-PCG) to 1e-6 of each probe's size, on a coupled scene (light_ball_in_water: a light
// ball rising in water, Chentanez et al. 2006's eq. 7 by Schur-complement CG) and a fluid-only
// one (pipe_flow, coarsened).
// Only the first process writes the output folder; a serial solver with two processes is refused
// by validate and run alike (exit 2, naming the key).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_helpers.hpp"
#include "csv.hpp"
#include "tests/test_support.hpp"

namespace fs = std::filesystem;
using namespace tetfsi::test;
using nlohmann::json;

namespace {

/// Open MPI's mpirun with two processes on however many cores there are (as root too: CI).
std::string mpirun2() {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -n 2 --oversubscribe " +
         std::string(TETFSI_BINARY) + " ";
}

struct Runs {
  TempDir dir;
  int serial_status = -1, parallel_status = -1;
  std::string serial_log, parallel_log;
  fs::path serial_out, parallel_out;

  /// Runs `scene` as it is on one process and with fluid.solver.type "petsc" on two.
  Runs(const std::string& name, json scene) : dir(name), serial_out(dir.path() / "serial"), parallel_out(dir.path() / "mpi") {
    const fs::path serial_file = dir.path() / "serial.json", parallel_file = dir.path() / "mpi.json";
    std::ofstream(serial_file) << scene.dump(2);
    scene["fluid"]["solver"]["type"] = "petsc";
    std::ofstream(parallel_file) << scene.dump(2);
    serial_log = tetfsi_cmd("run " + serial_file.string() + " --out " + serial_out.string() + " --quiet --threads 1",
                            &serial_status);
    parallel_log = run_command(mpirun2() + "run " + parallel_file.string() + " --out " + parallel_out.string() +
                                   " --quiet --threads 1 2>&1",
                               &parallel_status);
  }

  /// Both runs ended with exit 0 and wrote at least `rows` probes rows.
  ::testing::AssertionResult succeeded(std::size_t rows) const {
    if (serial_status != 0) return ::testing::AssertionFailure() << "one process: " << serial_log;
    if (parallel_status != 0) return ::testing::AssertionFailure() << "mpirun -n 2: " << parallel_log;
    if (serial_probes().rows.size() < rows) return ::testing::AssertionFailure() << "too few probes rows";
    return ::testing::AssertionSuccess();
  }
  Csv serial_probes() const { return read_csv(serial_out / "probes.csv"); }
  Csv parallel_probes() const { return read_csv(parallel_out / "probes.csv"); }
};

/// The probes.csv columns of each probe of `probes` (x, y, z of a vector probe together).
std::vector<std::vector<std::string>> probe_columns(const json& probes) {
  std::vector<std::vector<std::string>> groups;
  for (const auto& probe : probes) {
    const std::string name = probe["name"];
    if (probe["kind"] == "point_displacement") groups.push_back({name + "_x", name + "_y", name + "_z"});
    else groups.push_back({name});
  }
  return groups;
}

/// Largest difference of the probes.csv rows of two runs, per column, relative to the largest
/// magnitude of the probe the column belongs to (`groups`: columns of one probe, e.g. x, y, z)
/// over the run.
double largest_relative_difference(const Csv& a, const Csv& b, const std::vector<std::vector<std::string>>& groups) {
  EXPECT_EQ(a.header, b.header);
  EXPECT_EQ(a.rows.size(), b.rows.size());
  double worst = 0;
  for (const auto& group : groups) {
    double size = 0, difference = 0;
    for (std::size_t r = 0; r < std::min(a.rows.size(), b.rows.size()); ++r)
      for (const auto& column : group) {
        size = std::max(size, std::fabs(a.at(r, column)));
        difference = std::max(difference, std::fabs(a.at(r, column) - b.at(r, column)));
      }
    EXPECT_GT(size, 0) << group.front();
    worst = std::max(worst, difference / size);
  }
  return worst;
}

}  // namespace

TEST(MpiRun, CoupledProbesMatchOneProcess) {
  json scene = committed("light_ball_in_water.json");
  scene["fluid"]["solver"]["tolerance"] = 1e-10;
  const Runs runs("mpi_coupled", scene);
  ASSERT_TRUE(runs.succeeded(8));
  EXPECT_LT(largest_relative_difference(runs.serial_probes(), runs.parallel_probes(), probe_columns(scene["probes"])),
            1e-6);
  // The coupled solve ran its preconditioner on PETSc, over two processes, and only the first
  // process wrote: one run.log, whose record says so.
  const std::string log = read_text(runs.parallel_out / "run.log");
  EXPECT_NE(log.find("2 MPI processes"), std::string::npos) << log;
  EXPECT_NE(log.find("pressure solver: PETSc CG + BoomerAMG"), std::string::npos);
  EXPECT_EQ(read_csv(runs.parallel_out / "stats.csv").rows.size(), read_csv(runs.serial_out / "stats.csv").rows.size());
}

TEST(MpiRun, FluidProbesMatchOneProcess) {
  json scene = committed("pipe_flow.json");
  scene["mesh"]["edge_length"] = 0.04;
  scene["simulation"]["end_time"] = 0.3;
  scene["fluid"]["solver"]["tolerance"] = 1e-10;
  const Runs runs("mpi_fluid", scene);
  ASSERT_TRUE(runs.succeeded(15));
  EXPECT_LT(largest_relative_difference(runs.serial_probes(), runs.parallel_probes(), probe_columns(scene["probes"])),
            1e-6);
  EXPECT_NE(read_text(runs.parallel_out / "run.log").find("2 MPI processes"), std::string::npos);
}

TEST(MpiRun, SerialSolverWithTwoProcessesIsRefusedByValidateAndRun) {
  TempDir dir("mpi_refused");
  const fs::path file = dir.path() / "scene.json";
  std::ofstream(file) << committed("light_ball_in_water.json").dump(2);
  for (const std::string command : {"validate " + file.string(), "run " + file.string() + " --out " +
                                                                       (dir.path() / "out").string() + " --quiet"}) {
    int status = -1;
    const std::string log = run_command(mpirun2() + command + " 2>&1", &status);
    EXPECT_EQ(status, 2) << command << "\n" << log;
    EXPECT_NE(log.find("/fluid/solver/type"), std::string::npos) << log;
  }
}
