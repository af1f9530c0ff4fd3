#pragma once
/// @file static_steps.hpp
/// A static analysis in a runner (tet and hex8 solids): solid::solve_static from load factor 0 to
/// 1, each converged load step kept (its state is output frame k and probes.csv row k, time = load
/// factor), the Newton log to run.log and <name>_load_steps.csv.
#include <Eigen/Core>
#include <string>
#include <vector>

#include <spdlog/logger.h>

#include "apps/run/output.hpp"
#include "solid/analysis/static_solver.hpp"

namespace tetfsi::run {

struct StaticSteps {
  std::vector<double> load_factors;         ///< 0 (rest) first, then each converged step
  std::vector<Eigen::VectorXd> states;      ///< u per entry of load_factors [m]
  std::vector<solid::StepLog> logs;         ///< per converged step
  std::vector<double> moments;              ///< reaction moment of the first moment_rotation face [N m]
  double assembly_seconds = 0, solve_seconds = 0;
};

/// Solves the static problem of solid `name`.
/// @throws RunError on non-convergence, InputError on inconsistent boundary conditions
StaticSteps solve_in_steps(const std::string& name, const solid::ElasticModel& model,
                           const solid::BoundaryConditions& bc, const solid::StaticOptions& options,
                           spdlog::logger& log);

/// The state of the last step with load factor <= lambda (+1e-12): solids of one scene may reach
/// different intermediate load factors (step cuts); lambda < 0 gives the final state.
const Eigen::VectorXd& state_at(const StaticSteps& steps, double lambda);

/// Writes <name>_load_steps.csv: load factor, iterations, cuts, final residual ratio, reaction moment,
/// solves with the projected tangent (the exact one not positive definite).
void write_load_steps(Output& out, const std::string& name, const StaticSteps& steps);

/// Setup statistics of static solids: load steps, Newton iterations, most iterations in a step, cuts.
std::vector<double> static_totals(const std::vector<const StaticSteps*>& solids);

}  // namespace tetfsi::run
