#include "coupling/solver_comparison.hpp"

#include <stdexcept>

#include "support/stopwatch.hpp"

namespace tetfsi::coupling {

SolverComparison::SolverComparison(const std::vector<std::string>& names, const CoupledSolverOptions& coupled_options,
                                   const fluid::SolverOptions& fluid_options)
    : names_(names), fluid_options_(fluid_options) {
  CoupledSolverOptions options;
  options.tolerance = coupled_options.tolerance;
  options.max_iterations = coupled_options.max_iterations;
  for (const std::string& name : names_) {
    if (name == "projection") solvers_.push_back(nullptr);
    else if (name == "bicgstab" || name == "umfpack") solvers_.push_back(make_coupled_solver(parse_coupled_solver_kind(name), options));
    else throw std::invalid_argument("compare_solvers: unknown solver '" + name + "' (bicgstab, umfpack, projection)");
  }
}

SolverComparison::~SolverComparison() = default;

std::vector<ComparedSolve> SolverComparison::run(const CoupledSystem& system, const Eigen::VectorXd& u0,
                                                 const Eigen::VectorXd& p0) const {
  std::vector<ComparedSolve> out;
  for (std::size_t k = 0; k < names_.size(); ++k) {
    ComparedSolve c;
    c.name = names_[k];
    const Stopwatch clock;
    try {
      if (solvers_[k]) {
        Eigen::VectorXd u = u0, p = p0;
        c.iterations = solvers_[k]->solve(system, u, p).iterations;
      } else if (system.num_pressures() > 0) {
        Eigen::VectorXd p = p0;
        c.iterations = fluid::solve_spd(system.P, system.r, p, fluid_options_).iterations;
      }
    } catch (const CoupledSolveError& e) {
      c.failure = e.what();
    } catch (const fluid::SolverError& e) {
      c.failure = e.what();
    }
    c.seconds = clock.seconds();
    out.push_back(c);
  }
  return out;
}

}  // namespace tetfsi::coupling
